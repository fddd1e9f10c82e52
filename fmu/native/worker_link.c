/*
 * worker_link.c - starts the NC worker and talks to it (see worker_link.h).
 *
 * The worker is the Python runtime bundled in the FMU, resources/runtime/bin/python, started with
 * posix_spawn() in isolated mode (-I: no PYTHON* variable, no user site; -S: no site module) and an
 * environment of its own that holds nothing of the host's but the library path of the bundled
 * libpython.  Its sys.path is the runtime's python._pth: the zipped standard library, its extension
 * modules and the resources folder.  Nothing of a Python the host may have is touched: the host can
 * be FMPy on another Python version, and two instances are two processes.
 *
 * The socket pair is the worker's file descriptor 3.  Messages, little-endian, each preceded by the
 * length of its body as a uint32:
 *     request  uint8 operation, then its arguments (see the OP_ constants)
 *     answer   int32 status, uint32 n, n x (int32 status, uint32 length, message bytes),
 *              uint32 m, m x float64 values, then for the first answer the kinds of the variables
 *              (one byte each, in value-reference order)
 * Sets are queued here and sent with the next request that waits for an answer: a host that sets
 * 500 inputs one call each costs one round trip, not 500.  A value equal to the one sent last for
 * the same variable is not sent again (a PLC master writes its whole output image every cycle; the
 * NC sees the same bytes either way).  Gets are answered from the values the
 * worker sends back with each step: the references the host read since the previous step, read again
 * after this one (the NC's outputs change only in a step, an input only when it is set).
 */
#define _DEFAULT_SOURCE /* socketpair, MSG_NOSIGNAL, F_DUPFD_CLOEXEC with glibc */

#include "worker_link.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

enum {
    OP_SETUP = 1,
    OP_ENTER_INITIALIZATION = 2,
    OP_EXIT_INITIALIZATION = 3,
    OP_SET = 4,
    OP_GET = 5,
    OP_STEP = 6,
    OP_TERMINATE = 7,
    OP_RESET = 8,
    OP_FREE = 9,
};

enum { WORKER_FD = 3, FIRST_PRIVATE_FD = 10 };
static const char RUNTIME_PYTHON[] = "runtime/bin/python";
static const char RUNTIME_LIBRARIES[] = "runtime/lib";
static const char WORKER_SCRIPT[] = "vc_nc_worker.py";

typedef struct {
    unsigned char *data;
    size_t length;
    size_t capacity;
} Buffer;

struct VcWorker {
    pid_t pid;
    int socket;
    bool dead; /* the worker ended or the link broke: only stop is left */
    bool logging_on;
    VcLogFunction *log;
    void *log_context;
    char *instance_name;
    size_t variable_count;
    unsigned char *kinds;      /* per value reference: VcKind */
    double *cached;            /* per value reference: the last value the worker sent */
    unsigned char *valid;      /* per value reference: cached holds the present value */
    unsigned char *read;       /* per value reference: the host reads it; prefetched after each step */
    double *sent;              /* per value reference: the value set last */
    unsigned char *was_sent;   /* per value reference: sent holds a value (not after a reset) */
    uint32_t *prefetch;        /* the references with read set, for the step request */
    size_t prefetch_count;
    size_t queued_sets;        /* set requests in outgoing, not yet answered */
    Buffer outgoing;
    Buffer incoming;
    double *scratch;
    size_t scratch_capacity;
};

/* ------------------------------------------------------------------------ buffers */
static bool reserve(Buffer *buffer, size_t extra)
{
    if (buffer->length + extra <= buffer->capacity) {
        return true;
    }
    size_t capacity = buffer->capacity ? buffer->capacity : 4096;
    while (capacity < buffer->length + extra) {
        capacity *= 2;
    }
    unsigned char *data = realloc(buffer->data, capacity);
    if (data == NULL) {
        return false;
    }
    buffer->data = data;
    buffer->capacity = capacity;
    return true;
}

static void append(Buffer *buffer, const void *data, size_t size)
{
    memcpy(buffer->data + buffer->length, data, size); /* reserve() came first */
    buffer->length += size;
}

static void append_u8(Buffer *buffer, uint8_t value) { append(buffer, &value, sizeof value); }
static void append_u32(Buffer *buffer, uint32_t value) { append(buffer, &value, sizeof value); }
static void append_f64(Buffer *buffer, double value) { append(buffer, &value, sizeof value); }

/* Starts a request: its length is filled in by finish_request(). */
static size_t begin_request(VcWorker *worker, uint8_t operation, size_t payload)
{
    if (!reserve(&worker->outgoing, sizeof(uint32_t) + 1 + payload)) {
        return SIZE_MAX;
    }
    size_t start = worker->outgoing.length;
    append_u32(&worker->outgoing, 0);
    append_u8(&worker->outgoing, operation);
    return start;
}

static void finish_request(VcWorker *worker, size_t start)
{
    uint32_t length = (uint32_t)(worker->outgoing.length - start - sizeof(uint32_t));
    memcpy(worker->outgoing.data + start, &length, sizeof length);
}

/* ------------------------------------------------------------------------ messages */
static const char *category_of(VcStatus status)
{
    static const char *const CATEGORIES[] = {"logAll", "logStatusWarning", "logStatusWarning", "logStatusError",
                                             "logStatusFatal"};
    return CATEGORIES[status];
}

static void emit(VcWorker *worker, VcStatus status, const char *category, const char *message)
{
    if (worker->log != NULL && (worker->logging_on || status >= VC_WARNING)) {
        worker->log(worker->log_context, status, category, message);
    }
}

void vc_log(VcWorker *worker, VcStatus status, const char *message)
{
    emit(worker, status, category_of(status), message);
}

static void broken(VcWorker *worker, const char *what)
{
    char message[512];
    int wait_status = 0;
    if (worker->pid > 0 && waitpid(worker->pid, &wait_status, 0) == worker->pid) {
        worker->pid = 0;
        if (WIFSIGNALED(wait_status)) {
            snprintf(message, sizeof message, "%s: the NC's worker process ended by signal %d (%s)", what,
                     WTERMSIG(wait_status), strsignal(WTERMSIG(wait_status)));
        } else {
            snprintf(message, sizeof message, "%s: the NC's worker process ended with exit status %d", what,
                     WEXITSTATUS(wait_status));
        }
    } else {
        snprintf(message, sizeof message, "%s: the link to the NC's worker process broke (%s)", what,
                 strerror(errno));
    }
    worker->dead = true;
    emit(worker, VC_FATAL, "logStatusFatal", message);
}

static bool send_all(VcWorker *worker)
{
    size_t sent = 0;
    while (sent < worker->outgoing.length) {
        ssize_t done = send(worker->socket, worker->outgoing.data + sent, worker->outgoing.length - sent,
                            MSG_NOSIGNAL);
        if (done < 0 && errno == EINTR) {
            continue;
        }
        if (done <= 0) {
            return false;
        }
        sent += (size_t)done;
    }
    worker->outgoing.length = 0;
    return true;
}

static bool receive_exactly(VcWorker *worker, void *into, size_t size)
{
    size_t received = 0;
    while (received < size) {
        ssize_t done = recv(worker->socket, (char *)into + received, size - received, 0);
        if (done < 0 && errno == EINTR) {
            continue;
        }
        if (done <= 0) {
            errno = done == 0 ? EPIPE : errno;
            return false;
        }
        received += (size_t)done;
    }
    return true;
}

typedef struct {
    VcStatus status;
    const unsigned char *values; /* float64, unaligned */
    size_t value_count;
    const unsigned char *rest;
    size_t rest_length;
} Answer;

static bool take_u32(const unsigned char **cursor, const unsigned char *end, uint32_t *value)
{
    if ((size_t)(end - *cursor) < sizeof *value) {
        return false;
    }
    memcpy(value, *cursor, sizeof *value);
    *cursor += sizeof *value;
    return true;
}

/* Reads one answer into worker->incoming and passes its messages to the logger. */
static bool receive_answer(VcWorker *worker, Answer *answer)
{
    uint32_t length;
    if (!receive_exactly(worker, &length, sizeof length)) {
        return false;
    }
    worker->incoming.length = 0;
    if (!reserve(&worker->incoming, (size_t)length + 1) || !receive_exactly(worker, worker->incoming.data, length)) {
        return false;
    }
    const unsigned char *cursor = worker->incoming.data;
    const unsigned char *end = cursor + length;
    uint32_t status, message_count, value_count;
    if (!take_u32(&cursor, end, &status) || !take_u32(&cursor, end, &message_count)) {
        errno = EPROTO;
        return false;
    }
    for (uint32_t index = 0; index < message_count; ++index) {
        uint32_t message_status, message_length;
        if (!take_u32(&cursor, end, &message_status) || !take_u32(&cursor, end, &message_length) ||
            (size_t)(end - cursor) < message_length) {
            errno = EPROTO;
            return false;
        }
        char *message = malloc((size_t)message_length + 1);
        if (message != NULL) {
            memcpy(message, cursor, message_length);
            message[message_length] = '\0';
            VcStatus level = message_status <= VC_FATAL ? (VcStatus)message_status : VC_FATAL;
            emit(worker, level, category_of(level), message);
            free(message);
        }
        cursor += message_length;
    }
    if (!take_u32(&cursor, end, &value_count) || (size_t)(end - cursor) / sizeof(double) < value_count) {
        errno = EPROTO;
        return false;
    }
    answer->status = status <= VC_FATAL ? (VcStatus)status : VC_FATAL;
    answer->values = cursor;
    answer->value_count = value_count;
    answer->rest = cursor + value_count * sizeof(double);
    answer->rest_length = (size_t)(end - answer->rest);
    return true;
}

static double value_at(const Answer *answer, size_t index)
{
    double value;
    memcpy(&value, answer->values + index * sizeof value, sizeof value);
    return value;
}

/* Sends what is queued (the sets, then the request just added), reads the sets' answers and the
 * request's; the request's answer stays in worker->incoming. */
static VcStatus exchange(VcWorker *worker, const char *what, Answer *answer)
{
    if (worker->dead) {
        emit(worker, VC_ERROR, "logStatusError", "the NC's worker process has ended; only freeing the instance is left");
        return VC_ERROR;
    }
    if (!send_all(worker)) {
        broken(worker, what);
        return VC_FATAL;
    }
    VcStatus worst_set = VC_OK;
    for (; worker->queued_sets > 0; --worker->queued_sets) {
        Answer set_answer;
        if (!receive_answer(worker, &set_answer)) {
            worker->queued_sets = 0;
            broken(worker, what);
            return VC_FATAL;
        }
        worst_set = set_answer.status > worst_set ? set_answer.status : worst_set;
    }
    if (!receive_answer(worker, answer)) {
        broken(worker, what);
        return VC_FATAL;
    }
    if (worst_set == VC_FATAL) {
        answer->status = VC_FATAL;
    }
    if (answer->status == VC_FATAL) {
        worker->dead = true;
    }
    return answer->status;
}

static void forget_values(VcWorker *worker)
{
    memset(worker->valid, 0, worker->variable_count);
}

static VcStatus simple_request(VcWorker *worker, uint8_t operation, const char *what)
{
    size_t start = begin_request(worker, operation, 0);
    if (start == SIZE_MAX) {
        emit(worker, VC_FATAL, "logStatusFatal", "out of memory");
        return VC_FATAL;
    }
    finish_request(worker, start);
    forget_values(worker);
    Answer answer;
    return exchange(worker, what, &answer);
}

/* ------------------------------------------------------------------------ starting the worker */
static char *joined(const char *directory, const char *name)
{
    size_t length = strlen(directory);
    bool slash = length > 0 && directory[length - 1] == '/';
    size_t size = length + 1 + strlen(name) + 1;
    char *path = malloc(size);
    if (path != NULL) {
        snprintf(path, size, "%s%s%s", directory, slash ? "" : "/", name);
    }
    return path;
}

/* Hosts unzip FMUs with libraries that drop the file modes (Python's zipfile, for one): give the
 * bundled interpreter its execute bit back if it lost it. */
static void make_executable(const char *path)
{
    if (access(path, X_OK) != 0) {
        chmod(path, 0755); /* the mode the export gave it; stat() would raise the glibc floor to 2.33 */
    }
}

static bool spawn(VcWorker *worker, const char *resources_dir, const char *token, int fmi_version)
{
    char *python = joined(resources_dir, RUNTIME_PYTHON);
    char *libraries = joined(resources_dir, RUNTIME_LIBRARIES);
    char *script = joined(resources_dir, WORKER_SCRIPT);
    char *library_path = libraries ? malloc(strlen(libraries) + sizeof "LD_LIBRARY_PATH=") : NULL;
    bool started = false;
    int pair[2] = {-1, -1};
    int child_end = -1;
    char version[16];
    snprintf(version, sizeof version, "%d", fmi_version);
    char message[1024];
    if (python == NULL || script == NULL || library_path == NULL) {
        emit(worker, VC_FATAL, "logStatusFatal", "out of memory");
        goto done;
    }
    sprintf(library_path, "LD_LIBRARY_PATH=%s", libraries);
    if (access(python, R_OK) != 0 || access(script, R_OK) != 0) {
        snprintf(message, sizeof message,
                 "%s: the FMU's bundled Python runtime is missing (%s); is %s the resources folder of a"
                 " self-contained FMU of the VC harness?", access(python, R_OK) ? python : script, strerror(errno),
                 resources_dir);
        emit(worker, VC_FATAL, "logStatusFatal", message);
        goto done;
    }
    make_executable(python);
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, pair) != 0) {
        snprintf(message, sizeof message, "cannot create the socket pair to the NC's worker: %s", strerror(errno));
        emit(worker, VC_FATAL, "logStatusFatal", message);
        goto done;
    }
    /* above the descriptors dup2() writes to, so that no descriptor is its own target */
    child_end = fcntl(pair[1], F_DUPFD_CLOEXEC, FIRST_PRIVATE_FD);
    worker->socket = fcntl(pair[0], F_DUPFD_CLOEXEC, FIRST_PRIVATE_FD);
    close(pair[0]);
    close(pair[1]);
    if (child_end < 0 || worker->socket < 0) {
        snprintf(message, sizeof message, "cannot set up the socket to the NC's worker: %s", strerror(errno));
        emit(worker, VC_FATAL, "logStatusFatal", message);
        goto done;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, child_end, WORKER_FD);
    char *const arguments[] = {python, "-I", "-S", "-B", script, "3", (char *)resources_dir,
                               worker->instance_name, (char *)token, version, NULL};
    char *const environment[] = {library_path, NULL};
    int failed = posix_spawn(&worker->pid, python, &actions, NULL, arguments, environment);
    posix_spawn_file_actions_destroy(&actions);
    if (failed != 0) {
        worker->pid = 0;
        snprintf(message, sizeof message, "cannot start the NC's worker %s: %s", python, strerror(failed));
        emit(worker, VC_FATAL, "logStatusFatal", message);
        goto done;
    }
    started = true;
done:
    if (child_end >= 0) {
        close(child_end);
    }
    free(python);
    free(libraries);
    free(script);
    free(library_path);
    return started;
}

VcWorker *vc_worker_start(const char *resources_dir, const char *instance_name, const char *token,
                          int fmi_version, bool logging_on, VcLogFunction *log, void *log_context)
{
    VcWorker *worker = calloc(1, sizeof *worker);
    if (worker == NULL) {
        return NULL;
    }
    worker->socket = -1;
    worker->logging_on = logging_on;
    worker->log = log;
    worker->log_context = log_context;
    worker->instance_name = strdup(instance_name ? instance_name : "");
    if (worker->instance_name == NULL || !spawn(worker, resources_dir, token ? token : "", fmi_version)) {
        vc_worker_stop(worker);
        return NULL;
    }
    Answer hello; /* the worker answers once it has loaded the machine, or says why it cannot */
    if (!receive_answer(worker, &hello)) {
        broken(worker, "fmi Instantiate");
        vc_worker_stop(worker);
        return NULL;
    }
    if (hello.status >= VC_ERROR) {
        vc_worker_stop(worker);
        return NULL;
    }
    size_t count = hello.rest_length;
    worker->variable_count = count;
    worker->kinds = malloc(count + 1);
    worker->cached = calloc(count + 1, sizeof(double));
    worker->valid = calloc(count + 1, 1);
    worker->read = calloc(count + 1, 1);
    worker->prefetch = calloc(count + 1, sizeof(uint32_t));
    worker->sent = calloc(count + 1, sizeof(double));
    worker->was_sent = calloc(count + 1, 1);
    if (!worker->kinds || !worker->cached || !worker->valid || !worker->read || !worker->prefetch || !worker->sent ||
        !worker->was_sent) {
        emit(worker, VC_FATAL, "logStatusFatal", "out of memory");
        vc_worker_stop(worker);
        return NULL;
    }
    memcpy(worker->kinds, hello.rest, count);
    return worker;
}

void vc_worker_stop(VcWorker *worker)
{
    if (worker == NULL) {
        return;
    }
    if (worker->socket >= 0) {
        if (!worker->dead) {
            worker->outgoing.length = 0;
            worker->queued_sets = 0;
            size_t start = begin_request(worker, OP_FREE, 0);
            if (start != SIZE_MAX) {
                finish_request(worker, start);
                send_all(worker); /* the worker answers nothing and exits */
            }
        }
        close(worker->socket); /* a worker still reading sees the end of its input and exits */
    }
    if (worker->pid > 0) {
        while (waitpid(worker->pid, NULL, 0) < 0 && errno == EINTR) {
        }
    }
    free(worker->instance_name);
    free(worker->kinds);
    free(worker->cached);
    free(worker->valid);
    free(worker->read);
    free(worker->prefetch);
    free(worker->sent);
    free(worker->was_sent);
    free(worker->outgoing.data);
    free(worker->incoming.data);
    free(worker->scratch);
    free(worker);
}

void vc_set_logging(VcWorker *worker, bool logging_on) { worker->logging_on = logging_on; }

/* Room for count doubles, the conversions' (valid until the next call on the worker); NULL without memory. */
static double *scratch(VcWorker *worker, size_t count)
{
    if (count > worker->scratch_capacity) {
        double *scratch = realloc(worker->scratch, count * sizeof(double));
        if (scratch == NULL) {
            return NULL;
        }
        worker->scratch = scratch;
        worker->scratch_capacity = count;
    }
    if (worker->scratch == NULL && count == 0) {
        return worker->cached; /* nothing to convert: any valid address does */
    }
    return worker->scratch;
}

/* ------------------------------------------------------------------------ the life cycle */
VcStatus vc_setup(VcWorker *worker, double start_time)
{
    size_t start = begin_request(worker, OP_SETUP, sizeof(double));
    if (start == SIZE_MAX) {
        return VC_FATAL;
    }
    append_f64(&worker->outgoing, start_time);
    finish_request(worker, start);
    Answer answer;
    return exchange(worker, "fmiSetupExperiment", &answer);
}

VcStatus vc_enter_initialization(VcWorker *worker)
{
    return simple_request(worker, OP_ENTER_INITIALIZATION, "fmiEnterInitializationMode");
}

VcStatus vc_exit_initialization(VcWorker *worker)
{
    return simple_request(worker, OP_EXIT_INITIALIZATION, "fmiExitInitializationMode");
}

VcStatus vc_terminate(VcWorker *worker) { return simple_request(worker, OP_TERMINATE, "fmiTerminate"); }

VcStatus vc_reset(VcWorker *worker)
{
    memset(worker->was_sent, 0, worker->variable_count); /* the inputs are back at their power-on values */
    return simple_request(worker, OP_RESET, "fmiReset");
}

VcStatus vc_do_step(VcWorker *worker, double current_time, double step_size)
{
    size_t count = worker->prefetch_count;
    size_t start = begin_request(worker, OP_STEP, 2 * sizeof(double) + sizeof(uint32_t) + count * sizeof(uint32_t));
    if (start == SIZE_MAX) {
        return VC_FATAL;
    }
    append_f64(&worker->outgoing, current_time);
    append_f64(&worker->outgoing, step_size);
    append_u32(&worker->outgoing, (uint32_t)count);
    append(&worker->outgoing, worker->prefetch, count * sizeof(uint32_t));
    finish_request(worker, start);
    forget_values(worker);
    Answer answer;
    VcStatus status = exchange(worker, "fmiDoStep", &answer);
    if (status != VC_FATAL && answer.value_count == count) {
        for (size_t index = 0; index < count; ++index) {
            uint32_t reference = worker->prefetch[index];
            worker->cached[reference] = value_at(&answer, index);
            worker->valid[reference] = 1;
        }
    }
    return status;
}

/* ------------------------------------------------------------------------ values */
static bool known(const VcWorker *worker, VcKind kind, uint32_t reference)
{
    return reference < worker->variable_count && worker->kinds[reference] == (unsigned char)kind;
}

VcStatus vc_set(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, const double *values)
{
    if (worker->dead) {
        emit(worker, VC_ERROR, "logStatusError", "the NC's worker process has ended; only freeing the instance is left");
        return VC_ERROR;
    }
    size_t changed = 0;
    for (size_t index = 0; index < count; ++index) {
        uint32_t reference = references[index];
        changed += !known(worker, kind, reference) || !worker->was_sent[reference] || worker->sent[reference] != values[index];
    }
    if (changed == 0) {
        return VC_OK;
    }
    size_t start = begin_request(worker, OP_SET, 1 + sizeof(uint32_t) + changed * (sizeof(uint32_t) + sizeof(double)));
    if (start == SIZE_MAX) {
        return VC_FATAL;
    }
    append_u8(&worker->outgoing, (uint8_t)kind);
    append_u32(&worker->outgoing, (uint32_t)changed);
    for (int pass = 0; pass < 2; ++pass) { /* the references, then the values */
        for (size_t index = 0; index < count; ++index) {
            uint32_t reference = references[index];
            bool known_reference = known(worker, kind, reference);
            if (known_reference && worker->was_sent[reference] && worker->sent[reference] == values[index]) {
                continue;
            }
            if (pass == 0) {
                append_u32(&worker->outgoing, reference);
            } else {
                append_f64(&worker->outgoing, values[index]);
                if (known_reference) {
                    worker->sent[reference] = values[index];
                    worker->was_sent[reference] = 1;
                    worker->valid[reference] = 0; /* read back through the worker: it may refuse the value */
                }
            }
        }
    }
    finish_request(worker, start);
    ++worker->queued_sets;
    return VC_OK;
}

static void remember_read(VcWorker *worker, uint32_t reference)
{
    if (!worker->read[reference]) {
        worker->read[reference] = 1;
        worker->prefetch[worker->prefetch_count++] = reference;
    }
}

VcStatus vc_get(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, double *values)
{
    bool all_cached = !worker->dead;
    for (size_t index = 0; index < count && all_cached; ++index) {
        all_cached = known(worker, kind, references[index]) && worker->valid[references[index]];
    }
    if (all_cached) {
        for (size_t index = 0; index < count; ++index) {
            values[index] = worker->cached[references[index]];
        }
        return VC_OK;
    }
    size_t start = begin_request(worker, OP_GET, 1 + sizeof(uint32_t) + count * sizeof(uint32_t));
    if (start == SIZE_MAX) {
        return VC_FATAL;
    }
    append_u8(&worker->outgoing, (uint8_t)kind);
    append_u32(&worker->outgoing, (uint32_t)count);
    append(&worker->outgoing, references, count * sizeof(uint32_t));
    finish_request(worker, start);
    Answer answer;
    VcStatus status = exchange(worker, "fmiGet", &answer);
    if (status >= VC_ERROR) {
        return status;
    }
    if (answer.value_count != count) {
        errno = EPROTO;
        broken(worker, "fmiGet");
        return VC_FATAL;
    }
    for (size_t index = 0; index < count; ++index) {
        uint32_t reference = references[index];
        values[index] = value_at(&answer, index);
        worker->cached[reference] = values[index]; /* the worker checked the references */
        worker->valid[reference] = 1;
        remember_read(worker, reference);
    }
    return status;
}

/* ------------------------------------------------------------------------ values of other C types */
VcStatus vc_set_ints(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, const int *values)
{
    double *converted = scratch(worker, count);
    if (converted == NULL) {
        return VC_FATAL;
    }
    for (size_t index = 0; index < count; ++index) {
        converted[index] = (double)values[index];
    }
    return vc_set(worker, kind, references, count, converted);
}

VcStatus vc_get_ints(VcWorker *worker, VcKind kind, const uint32_t *references, size_t count, int *values)
{
    double *converted = scratch(worker, count);
    if (converted == NULL) {
        return VC_FATAL;
    }
    VcStatus status = vc_get(worker, kind, references, count, converted);
    if (status < VC_ERROR) {
        for (size_t index = 0; index < count; ++index) {
            values[index] = (int)converted[index];
        }
    }
    return status;
}

VcStatus vc_set_bools(VcWorker *worker, const uint32_t *references, size_t count, const bool *values)
{
    double *converted = scratch(worker, count);
    if (converted == NULL) {
        return VC_FATAL;
    }
    for (size_t index = 0; index < count; ++index) {
        converted[index] = values[index] ? 1.0 : 0.0;
    }
    return vc_set(worker, VC_BOOLEAN, references, count, converted);
}

VcStatus vc_get_bools(VcWorker *worker, const uint32_t *references, size_t count, bool *values)
{
    double *converted = scratch(worker, count);
    if (converted == NULL) {
        return VC_FATAL;
    }
    VcStatus status = vc_get(worker, VC_BOOLEAN, references, count, converted);
    if (status < VC_ERROR) {
        for (size_t index = 0; index < count; ++index) {
            values[index] = converted[index] != 0.0;
        }
    }
    return status;
}
