/*
 * worker_link.h - the FMU binary's side of the NC worker: a process of the Python runtime bundled in
 * the FMU's resources, started at instantiation and spoken to over a socket pair (see
 * fmu/worker.py for the other side and the message layout).
 *
 * Both FMI versions (fmi2.c, fmi3.c) are thin front ends on these functions.  Statuses are numbered
 * as fmi2Status and fmi3Status are (OK, Warning, Discard, Error, Fatal); values cross as doubles,
 * which hold every Boolean and every 32-bit integer exactly.
 */
#ifndef VC_WORKER_LINK_H
#define VC_WORKER_LINK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum { VC_OK = 0, VC_WARNING = 1, VC_DISCARD = 2, VC_ERROR = 3, VC_FATAL = 4 } VcStatus;

/* The kinds of variable, numbered as the worker numbers them (fmu/worker.py KIND_CODES). */
typedef enum { VC_REAL = 0, VC_INTEGER = 1, VC_BOOLEAN = 2 } VcKind;

/* Where messages go: the FMI version's logger, called with the instance's own context. */
typedef void VcLogFunction(void *context, VcStatus status, const char *category, const char *message);

typedef struct VcWorker VcWorker;

/* Starts the worker for the FMU whose resources folder is resources_dir (a plain path) and waits for
 * it to load the machine.  NULL when it cannot: the reason has gone to log. */
VcWorker *vc_worker_start(const char *resources_dir, const char *instance_name, const char *token,
                          int fmi_version, bool logging_on, VcLogFunction *log, void *log_context);

/* Ends the worker (it exits on its own when the socket closes) and frees everything. */
void vc_worker_stop(VcWorker *worker);

void vc_set_logging(VcWorker *worker, bool logging_on);

/* The life cycle; each waits for the worker's answer. */
VcStatus vc_setup(VcWorker *worker, double start_time);
VcStatus vc_enter_initialization(VcWorker *worker);
VcStatus vc_exit_initialization(VcWorker *worker);
VcStatus vc_do_step(VcWorker *worker, double current_time, double step_size);
VcStatus vc_terminate(VcWorker *worker);
VcStatus vc_reset(VcWorker *worker);

/* Values.  A set is queued and travels with the next call that needs an answer (its problems are
 * logged then); a get is answered from the values the worker sent with the last step when it has
 * them, otherwise it asks. */
VcStatus vc_set(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, const double *values);
VcStatus vc_get(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, double *values);

/* The same for int arrays (FMI 2.0 Integer and Boolean, FMI 3.0 Int32) and bool arrays (FMI 3.0 Boolean). */
VcStatus vc_set_ints(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, const int *values);
VcStatus vc_get_ints(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, int *values);
VcStatus vc_set_bools(VcWorker *worker, const uint32_t *references, size_t count, const bool *values);
VcStatus vc_get_bools(VcWorker *worker, const uint32_t *references, size_t count, bool *values);

/* Logs a message through the instance's logger (for the front ends' own checks). */
void vc_log(VcWorker *worker, VcStatus status, const char *message);

#endif
