/*
 * fmu_host.c - a minimal FMI 2.0 co-simulation host in C: the second importer of the VC harness
 * FMU next to FMPy.  It loads the FMU's binary with dlopen(), plays the PLC of a JOG of X1 on the
 * turn_mill machine (drives on, JOG mode, enables, traverse key plus held for 0.5 s), steps the FMU
 * in 10 ms communication steps and prints what it did and what the FMU answered.  On the way it
 * asks for one step the FMU must refuse (3 ms, not a whole number of 2 ms IPO cycles) and carries on.
 *
 * Build (the FMI headers are the ones FMPy ships in fmpy/c-code):
 *     gcc -std=c11 -Wall -Wextra -Werror -O1 -I<fmpy>/c-code fmu_host.c -ldl -o fmu_host
 *
 * Run:
 *     fmu_host FMU_DIR VARIABLES_FILE [NAME=VALUE ...]
 *
 *     FMU_DIR         the unzipped FMU (binaries/, resources/, modelDescription.xml)
 *     VARIABLES_FILE  what a host would otherwise read from modelDescription.xml (this host has no
 *                     XML parser), one item a line, '#' starts a comment:
 *                         modelIdentifier <identifier>
 *                         guid <guid>
 *                         variable <value reference> <Real|Integer|Boolean> <name>
 *     NAME=VALUE      a Real parameter set before initialisation, e.g. X1.startPosition=120
 *
 * Standard output, one record a line, "<kind> key=value ...", Reals as %.17g so that they read back
 * as the same double (a test replays the records in-process and compares):
 *     fmu model=turn_mill fmiVersion=2.0 typesPlatform=default
 *     parameter X1.startPosition=120             set before initialisation
 *     initialized t=0                            fmi2ExitInitializationMode returned
 *     set t=0.14999999999999999 X1.basic.out.enableCtrl=1   an input written before the step at t
 *     step t=0.40000000000000002 h=0.0030000000000000001 status=2   every fmi2DoStep and its status
 *     sample t=0.01 X1.position=0 ... Drives.ready=0   outputs at t (after initialisation, after each step)
 *     done
 * The FMU's log messages go to standard error, each as
 *     [fmu log] <instance> status=<n> (<name>) category=<category>: <message>
 *
 * Exit status: 0 when everything went as planned, 1 when the FMU failed or answered unexpectedly,
 * 2 for a bad command line or variables file.  A failure is reported on standard error as
 * "fmu_host: error: ...", after whatever the FMU logged about it.
 *
 * The self-contained FMU (the default of vc fmu export) needs nothing of this host's environment: the
 * test runs it with an empty one (env -i).  The lean FMU (--python host) runs the Python of the host
 * process and does not link libpython: it would need LD_PRELOAD=<libpython3.X.so> and that Python
 * first on PATH.
 */

#define _XOPEN_SOURCE 700 /* POSIX 2008 with XSI: getline, strdup, strtok_r, realpath */

#include <dlfcn.h>
#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

enum { EXIT_FMU_FAILED = 1, EXIT_BAD_USAGE = 2 };

/* ------------------------------------------------------------------------ the plan
 * The timeline counts communication steps rather than adding up seconds, so that every
 * communication point is k * 10 ms exactly as the FMU counts it (no drift from repeated sums). */
static const double COMMUNICATION_STEP_S = 0.010; /* 5 IPO cycles of 2 ms: turn_mill's PLC cycle */
static const double REFUSED_STEP_S = 0.003;       /* 1.5 IPO cycles: the unit must refuse it */
static const double START_TIME_S = 0.0;

enum {
    ENABLE_AXIS_AT_STEP = 15,       /* 0.15 s: Drives.ready follows Drives.on after 0.1 s */
    PRESS_JOG_KEY_AT_STEP = 20,     /* 0.20 s */
    REFUSED_STEP_AT_STEP = 40,      /* 0.40 s: in the middle of the traverse */
    RELEASE_JOG_KEY_AT_STEP = 70,   /* 0.70 s: the key was held for 0.5 s */
    STEP_COUNT = 90,                /* 0.90 s: X1 has braked and stands */
};

static const char *const SAMPLED_REALS[] = {
    "X1.position", "X1.velocity", "X1.physical", "X1.setpoint", "X1.followingError",
};
static const char *const SAMPLED_BOOLEANS[] = {
    "NC.basic.in.ncReady",                /* DB10.DBX108.7 */
    "MODEGROUP.basic.in.jogModeActive",   /* DB11.DBX6.2 */
    "X1.basic.in.posCtrlActive",          /* DB31.DBX61.5 */
    "X1.basic.in.isStationary",           /* DB31.DBX61.4 */
    "Drives.ready",                       /* plant input I6.1 */
};
#define COUNT_OF(array) (sizeof(array) / sizeof((array)[0]))

/* ------------------------------------------------------------------------ the variables file */
typedef enum { KIND_REAL, KIND_INTEGER, KIND_BOOLEAN } VariableKind;
static const char *const KIND_NAMES[] = {"Real", "Integer", "Boolean"};

typedef struct {
    fmi2ValueReference value_reference;
    VariableKind kind;
    char *name;
} Variable;

typedef struct {
    char *model_identifier;
    char *guid;
    Variable *variables;
    size_t count;
    size_t capacity;
} ModelInfo;

/* ------------------------------------------------------------------------ the loaded FMU */
typedef struct {
    void *library;
    fmi2Component component;
    bool instance_usable; /* false after fmi2Fatal: then no FMI function may be called any more */
    fmi2GetVersionTYPE *get_version;
    fmi2GetTypesPlatformTYPE *get_types_platform;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup_experiment;
    fmi2EnterInitializationModeTYPE *enter_initialization_mode;
    fmi2ExitInitializationModeTYPE *exit_initialization_mode;
    fmi2TerminateTYPE *terminate;
    fmi2DoStepTYPE *do_step;
    fmi2SetRealTYPE *set_real;
    fmi2SetIntegerTYPE *set_integer;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2GetRealTYPE *get_real;
    fmi2GetBooleanTYPE *get_boolean;
} Fmu;

/* The worst status the FMU logged since the last reset.  The FMU answers fmi2OK to a set call whose
 * value the NC refuses (it only logs fmi2Error, when the value reaches the NC), so the return value
 * alone does not tell whether a value was taken; every call is therefore judged by both.  The host
 * is single threaded and the FMU calls the logger on the calling thread, so a plain static suffices. */
static fmi2Status worst_logged_status = fmi2OK;

static const char *status_name(fmi2Status status)
{
    static const char *const names[] = {"fmi2OK", "fmi2Warning", "fmi2Discard", "fmi2Error", "fmi2Fatal",
                                        "fmi2Pending"};
    return (unsigned)status < COUNT_OF(names) ? names[status] : "unknown status";
}

/* The FMU's logger.  FMI 2.0 makes the message a printf format with the arguments that follow
 * (as FMPy's logger treats it too).  NULL is tolerated for the instance name and category. */
static void log_message(fmi2ComponentEnvironment environment, fmi2String instance_name, fmi2Status status,
                        fmi2String category, fmi2String message, ...)
{
    (void)environment;
    fprintf(stderr, "[fmu log] %s status=%d (%s) category=%s: ", instance_name ? instance_name : "?", (int)status,
            status_name(status), category ? category : "");
    va_list arguments;
    va_start(arguments, message);
    vfprintf(stderr, message ? message : "(no message)", arguments);
    va_end(arguments);
    fputc('\n', stderr);
    if (status > worst_logged_status && status != fmi2Pending) {
        worst_logged_status = status;
    }
}

/* The FMU may keep a pointer to the callbacks for the life of the instance: static storage. */
static const fmi2CallbackFunctions CALLBACKS = {
    .logger = log_message,
    .allocateMemory = calloc,
    .freeMemory = free,
    .stepFinished = NULL, /* asynchronous doStep is not asked for */
    .componentEnvironment = NULL,
};

/* ------------------------------------------------------------------------ failing */
static Fmu *fmu_to_release; /* freed on the way out of a failure, if it can still be */

static void release_fmu(Fmu *fmu)
{
    if (fmu->component != NULL && fmu->instance_usable) {
        fmu->free_instance(fmu->component);
    }
    fmu->component = NULL;
    /* The library is not dlclose()d: it has started a Python interpreter in this process, and
     * unloading the code under it would only invite trouble at exit. */
}

static void fail(int exit_status, const char *format, ...)
{
    fflush(stdout); /* the records so far stay in order before the error */
    fputs("fmu_host: error: ", stderr);
    va_list arguments;
    va_start(arguments, format);
    vfprintf(stderr, format, arguments);
    va_end(arguments);
    fputc('\n', stderr);
    if (fmu_to_release != NULL) {
        release_fmu(fmu_to_release);
    }
    exit(exit_status);
}

/* Judge an FMI call: fmi2OK or fmi2Warning, and nothing worse than a warning logged during it. */
static void check(Fmu *fmu, fmi2Status status, const char *call)
{
    if (status == fmi2Fatal) {
        fmu->instance_usable = false;
    }
    if (status != fmi2OK && status != fmi2Warning) {
        fail(EXIT_FMU_FAILED, "%s returned %d (%s); the FMU's log above says why", call, (int)status,
             status_name(status));
    }
    if (worst_logged_status >= fmi2Error) {
        fail(EXIT_FMU_FAILED, "%s returned %s but the FMU logged %s (see above)", call, status_name(status),
             status_name(worst_logged_status));
    }
}

/* ------------------------------------------------------------------------ reading the variables file */
static char *copy_text(const char *text)
{
    char *copy = strdup(text);
    if (copy == NULL) {
        fail(EXIT_FMU_FAILED, "out of memory");
    }
    return copy;
}

static void add_variable(ModelInfo *model, fmi2ValueReference value_reference, VariableKind kind, const char *name)
{
    if (model->count == model->capacity) {
        size_t capacity = model->capacity ? 2 * model->capacity : 256;
        Variable *grown = realloc(model->variables, capacity * sizeof *grown);
        if (grown == NULL) {
            fail(EXIT_FMU_FAILED, "out of memory");
        }
        model->variables = grown;
        model->capacity = capacity;
    }
    model->variables[model->count++] = (Variable){value_reference, kind, copy_text(name)};
}

static bool parse_kind(const char *text, VariableKind *kind)
{
    for (size_t index = 0; index < COUNT_OF(KIND_NAMES); ++index) {
        if (strcmp(text, KIND_NAMES[index]) == 0) {
            *kind = (VariableKind)index;
            return true;
        }
    }
    return false;
}

static bool parse_value_reference(const char *text, fmi2ValueReference *value_reference)
{
    char *end = NULL;
    unsigned long number = strtoul(text, &end, 10);
    if (text[0] < '0' || text[0] > '9' || *end != '\0' || number > UINT_MAX) {
        return false;
    }
    *value_reference = (fmi2ValueReference)number;
    return true;
}

static void read_model_info(const char *path, ModelInfo *model)
{
    FILE *file = fopen(path, "r");
    if (file == NULL) {
        fail(EXIT_BAD_USAGE, "cannot open the variables file %s", path);
    }
    char *line = NULL;
    size_t line_capacity = 0;
    unsigned line_number = 0;
    while (getline(&line, &line_capacity, file) != -1) {
        ++line_number;
        char *tokens[5];
        size_t token_count = 0;
        char *position = NULL;
        for (char *token = strtok_r(line, " \t\r\n", &position); token != NULL && token[0] != '#';
             token = strtok_r(NULL, " \t\r\n", &position)) {
            if (token_count == COUNT_OF(tokens)) {
                break; /* too many: reported below */
            }
            tokens[token_count++] = token;
        }
        if (token_count == 0) {
            continue; /* blank line or comment */
        }
        if (strcmp(tokens[0], "modelIdentifier") == 0 && token_count == 2) {
            free(model->model_identifier);
            model->model_identifier = copy_text(tokens[1]);
        } else if (strcmp(tokens[0], "guid") == 0 && token_count == 2) {
            free(model->guid);
            model->guid = copy_text(tokens[1]);
        } else if (strcmp(tokens[0], "variable") == 0 && token_count == 4) {
            fmi2ValueReference value_reference;
            VariableKind kind;
            if (!parse_value_reference(tokens[1], &value_reference) || !parse_kind(tokens[2], &kind)) {
                fail(EXIT_BAD_USAGE, "%s:%u: expected 'variable <value reference> <Real|Integer|Boolean> <name>'",
                     path, line_number);
            }
            add_variable(model, value_reference, kind, tokens[3]);
        } else {
            fail(EXIT_BAD_USAGE, "%s:%u: expected 'modelIdentifier <id>', 'guid <guid>' or 'variable <vr> <type> <name>'",
                 path, line_number);
        }
    }
    free(line);
    bool read_error = ferror(file);
    fclose(file);
    if (read_error) {
        fail(EXIT_BAD_USAGE, "cannot read the variables file %s", path);
    }
    if (model->model_identifier == NULL || model->guid == NULL || model->count == 0) {
        fail(EXIT_BAD_USAGE, "%s names no modelIdentifier, guid or variables", path);
    }
}

static const Variable *find_variable(const ModelInfo *model, const char *name, VariableKind kind)
{
    for (size_t index = 0; index < model->count; ++index) {
        const Variable *variable = &model->variables[index];
        if (strcmp(variable->name, name) == 0) {
            if (variable->kind != kind) {
                fail(EXIT_BAD_USAGE, "%s is of type %s; the host uses it as %s", name, KIND_NAMES[variable->kind],
                     KIND_NAMES[kind]);
            }
            return variable;
        }
    }
    fail(EXIT_BAD_USAGE, "the FMU has no variable %s (is it the turn_mill FMU?)", name);
    return NULL; /* not reached */
}

static void free_model_info(ModelInfo *model)
{
    for (size_t index = 0; index < model->count; ++index) {
        free(model->variables[index].name);
    }
    free(model->variables);
    free(model->model_identifier);
    free(model->guid);
}

/* ------------------------------------------------------------------------ loading the binary */
static void *resolve(Fmu *fmu, const char *symbol)
{
    dlerror(); /* clear an earlier error */
    void *address = dlsym(fmu->library, symbol);
    const char *error = dlerror();
    if (error != NULL || address == NULL) {
        fail(EXIT_FMU_FAILED, "the FMU's binary does not export %s: %s", symbol, error ? error : "NULL address");
    }
    return address;
}

/* ISO C converts no object pointer (what dlsym() returns) to a function pointer; POSIX guarantees
 * that the bits are the function's address, so they are copied (clean under -Wpedantic, too). */
#define RESOLVE(fmu, field, symbol)                                                        \
    do {                                                                                   \
        void *address = resolve((fmu), (symbol));                                          \
        _Static_assert(sizeof (fmu)->field == sizeof address, "function pointer size");    \
        memcpy(&(fmu)->field, &address, sizeof address);                                   \
    } while (0)

static void load_fmu(Fmu *fmu, const char *fmu_dir, const char *model_identifier)
{
    char binary_path[PATH_MAX];
    int length = snprintf(binary_path, sizeof binary_path, "%s/binaries/linux64/%s.so", fmu_dir, model_identifier);
    if (length < 0 || (size_t)length >= sizeof binary_path) {
        fail(EXIT_BAD_USAGE, "the FMU directory's path is too long");
    }
    /* RTLD_NOW: an unresolved symbol (libpython's, when it is not preloaded) shows here, with its
     * name, rather than as a crash at the first call. */
    fmu->library = dlopen(binary_path, RTLD_NOW | RTLD_LOCAL);
    if (fmu->library == NULL) {
        const char *error = dlerror();
        bool python_missing = strstr(error, "undefined symbol: Py") != NULL || strstr(error, "undefined symbol: _Py") != NULL;
        fail(EXIT_FMU_FAILED, "cannot load %s: %s%s", binary_path, error,
             python_missing ? "\n(a lean FMU, vc fmu export --python host, runs the host's Python: start this host"
                              " with LD_PRELOAD=<libpython3.X.so> and that Python's bin first on PATH)"
                            : "");
    }
    RESOLVE(fmu, get_version, "fmi2GetVersion");
    RESOLVE(fmu, get_types_platform, "fmi2GetTypesPlatform");
    RESOLVE(fmu, instantiate, "fmi2Instantiate");
    RESOLVE(fmu, free_instance, "fmi2FreeInstance");
    RESOLVE(fmu, setup_experiment, "fmi2SetupExperiment");
    RESOLVE(fmu, enter_initialization_mode, "fmi2EnterInitializationMode");
    RESOLVE(fmu, exit_initialization_mode, "fmi2ExitInitializationMode");
    RESOLVE(fmu, terminate, "fmi2Terminate");
    RESOLVE(fmu, do_step, "fmi2DoStep");
    RESOLVE(fmu, set_real, "fmi2SetReal");
    RESOLVE(fmu, set_integer, "fmi2SetInteger");
    RESOLVE(fmu, set_boolean, "fmi2SetBoolean");
    RESOLVE(fmu, get_real, "fmi2GetReal");
    RESOLVE(fmu, get_boolean, "fmi2GetBoolean");
}

/* fmuResourceLocation is a URI: file:// and the absolute path of resources/.  The path goes in
 * unencoded, which FMUs take as well as a percent-encoded one.  The directory is checked here so
 * that a wrong FMU directory is reported as such. */
static void resources_uri(const char *fmu_dir, char *uri, size_t size)
{
    char resources[PATH_MAX];
    int length = snprintf(resources, sizeof resources, "%s/resources", fmu_dir);
    if (length < 0 || (size_t)length >= sizeof resources) {
        fail(EXIT_BAD_USAGE, "the FMU directory's path is too long");
    }
    char absolute[PATH_MAX];
    if (realpath(resources, absolute) == NULL) {
        fail(EXIT_BAD_USAGE, "%s does not exist: is %s an unzipped FMU?", resources, fmu_dir);
    }
    length = snprintf(uri, size, "file://%s", absolute);
    if (length < 0 || (size_t)length >= size) {
        fail(EXIT_BAD_USAGE, "the FMU directory's path is too long");
    }
}

/* ------------------------------------------------------------------------ talking to the FMU */
typedef struct {
    Fmu *fmu;
    const ModelInfo *model;
    char call[512]; /* the FMI call under way, for the error message */
} Host;

static const char *describe_call(Host *host, const char *function, const char *name)
{
    snprintf(host->call, sizeof host->call, "%s(%s)", function, name);
    return host->call;
}

static void set_boolean(Host *host, double time, const char *name, bool value)
{
    const Variable *variable = find_variable(host->model, name, KIND_BOOLEAN);
    fmi2Boolean fmi_value = value ? fmi2True : fmi2False;
    worst_logged_status = fmi2OK;
    fmi2Status status = host->fmu->set_boolean(host->fmu->component, &variable->value_reference, 1, &fmi_value);
    check(host->fmu, status, describe_call(host, "fmi2SetBoolean", name));
    printf("set t=%.17g %s=%d\n", time, name, (int)fmi_value);
}

static void set_integer(Host *host, double time, const char *name, int value)
{
    const Variable *variable = find_variable(host->model, name, KIND_INTEGER);
    fmi2Integer fmi_value = value;
    worst_logged_status = fmi2OK;
    fmi2Status status = host->fmu->set_integer(host->fmu->component, &variable->value_reference, 1, &fmi_value);
    check(host->fmu, status, describe_call(host, "fmi2SetInteger", name));
    printf("set t=%.17g %s=%d\n", time, name, (int)fmi_value);
}

static void set_real_parameter(Host *host, const char *name, double value)
{
    const Variable *variable = find_variable(host->model, name, KIND_REAL);
    worst_logged_status = fmi2OK;
    fmi2Status status = host->fmu->set_real(host->fmu->component, &variable->value_reference, 1, &value);
    check(host->fmu, status, describe_call(host, "fmi2SetReal", name));
    printf("parameter %s=%.17g\n", name, value);
}

/* One record with the sampled outputs, each kind read in one call as a host would. */
static void sample(Host *host, double time)
{
    fmi2ValueReference real_references[COUNT_OF(SAMPLED_REALS)];
    fmi2Real reals[COUNT_OF(SAMPLED_REALS)];
    for (size_t index = 0; index < COUNT_OF(SAMPLED_REALS); ++index) {
        real_references[index] = find_variable(host->model, SAMPLED_REALS[index], KIND_REAL)->value_reference;
    }
    fmi2ValueReference boolean_references[COUNT_OF(SAMPLED_BOOLEANS)];
    fmi2Boolean booleans[COUNT_OF(SAMPLED_BOOLEANS)];
    for (size_t index = 0; index < COUNT_OF(SAMPLED_BOOLEANS); ++index) {
        boolean_references[index] =
            find_variable(host->model, SAMPLED_BOOLEANS[index], KIND_BOOLEAN)->value_reference;
    }
    worst_logged_status = fmi2OK;
    check(host->fmu, host->fmu->get_real(host->fmu->component, real_references, COUNT_OF(reals), reals), "fmi2GetReal");
    check(host->fmu,
          host->fmu->get_boolean(host->fmu->component, boolean_references, COUNT_OF(booleans), booleans),
          "fmi2GetBoolean");
    printf("sample t=%.17g", time);
    for (size_t index = 0; index < COUNT_OF(reals); ++index) {
        printf(" %s=%.17g", SAMPLED_REALS[index], reals[index]);
    }
    for (size_t index = 0; index < COUNT_OF(booleans); ++index) {
        printf(" %s=%d", SAMPLED_BOOLEANS[index], booleans[index] ? 1 : 0);
    }
    putchar('\n');
}

static bool read_boolean(Host *host, const char *name)
{
    const Variable *variable = find_variable(host->model, name, KIND_BOOLEAN);
    fmi2Boolean value = fmi2False;
    worst_logged_status = fmi2OK;
    check(host->fmu, host->fmu->get_boolean(host->fmu->component, &variable->value_reference, 1, &value),
          describe_call(host, "fmi2GetBoolean", name));
    return value != fmi2False;
}

static fmi2Status do_step(Host *host, double time, double step_size)
{
    worst_logged_status = fmi2OK;
    /* noSetFMUStatePriorToCurrentPoint: this host never goes back */
    fmi2Status status = host->fmu->do_step(host->fmu->component, time, step_size, fmi2True);
    printf("step t=%.17g h=%.17g status=%d\n", time, step_size, (int)status);
    return status;
}

/* ------------------------------------------------------------------------ the PLC's part */

/* What a basic PLC program gives at power-on (compare plc_stub/programs/basic_machine.py):
 * drives switched on, JOG, overrides at 100 % and active, measuring system 1 of X1. */
static void power_on_plc_outputs(Host *host, double time)
{
    set_boolean(host, time, "Drives.on", true);                                  /* Q0.0 */
    set_boolean(host, time, "MODEGROUP.basic.out.jogMode", true);                /* DB11.DBX0.2 */
    set_boolean(host, time, "CHAN1.basic.out.pathFeedrateOvr", true);            /* DB21.DBX6.7 */
    set_integer(host, time, "CHAN1.basic.out.pathFeedrateOvrFactor", 100);       /* DB21.DBB4, % */
    set_boolean(host, time, "X1.basic.out.enc1Activation", true);                /* DB31.DBX1.5 */
    set_boolean(host, time, "X1.basic.out.enableOvr", true);                     /* DB31.DBX1.7 */
    set_integer(host, time, "X1.basic.out.feedrateOvrFactor", 100);              /* DB31.DBB0, % */
}

/* Controller and pulse enable once the drives report ready, as the basic PLC program does. */
static void enable_x1(Host *host, double time)
{
    if (!read_boolean(host, "Drives.ready")) {
        fail(EXIT_FMU_FAILED, "the drives are not ready at t = %g s, %g s after Drives.on", time, time - START_TIME_S);
    }
    set_boolean(host, time, "X1.basic.out.enableCtrl", true);                    /* DB31.DBX2.1 */
    set_boolean(host, time, "X1.drive.out.enablePulses", true);                  /* DB31.DBX21.7 */
}

/* The step the FMU must refuse: it answers fmi2Discard, logs why, and stays where it was.  The FMI
 * 2.0 state machine lets a master only read values or terminate after a discarded step; this FMU
 * refuses before it computes anything (and keeps no FMI state machine), so the host steps on. */
static void demonstrate_refused_step(Host *host, double time)
{
    fmi2Status status = do_step(host, time, REFUSED_STEP_S);
    if (status != fmi2Discard) {
        fail(EXIT_FMU_FAILED, "a step of %g s at t = %g s returned %d (%s); expected fmi2Discard", REFUSED_STEP_S, time,
             (int)status, status_name(status));
    }
    if (worst_logged_status != fmi2Error) {
        fail(EXIT_FMU_FAILED, "the refused step was not logged as fmi2Error (worst logged: %s)",
             status_name(worst_logged_status));
    }
    fprintf(stderr, "fmu_host: the %g s step was refused as expected; carrying on at t = %g s\n", REFUSED_STEP_S, time);
}

static void run(Host *host)
{
    double time = START_TIME_S;
    power_on_plc_outputs(host, time);
    sample(host, time);
    for (int step = 0; step < STEP_COUNT; ++step) {
        time = START_TIME_S + step * COMMUNICATION_STEP_S;
        switch (step) {
        case ENABLE_AXIS_AT_STEP:
            enable_x1(host, time);
            break;
        case PRESS_JOG_KEY_AT_STEP:
            set_boolean(host, time, "X1.basic.out.traversKeyPlus", true);        /* DB31.DBX4.7 */
            break;
        case RELEASE_JOG_KEY_AT_STEP:
            set_boolean(host, time, "X1.basic.out.traversKeyPlus", false);
            break;
        case REFUSED_STEP_AT_STEP:
            demonstrate_refused_step(host, time);
            break;
        default:
            break;
        }
        check(host->fmu, do_step(host, time, COMMUNICATION_STEP_S), "fmi2DoStep");
        sample(host, START_TIME_S + (step + 1) * COMMUNICATION_STEP_S);
    }
}

/* ------------------------------------------------------------------------ main */
static void parse_parameter(const char *argument, char *name, size_t name_size, double *value)
{
    const char *equals = strchr(argument, '=');
    if (equals == NULL || equals == argument || (size_t)(equals - argument) >= name_size) {
        fail(EXIT_BAD_USAGE, "'%s' is not NAME=VALUE", argument);
    }
    memcpy(name, argument, (size_t)(equals - argument));
    name[equals - argument] = '\0';
    char *end = NULL;
    *value = strtod(equals + 1, &end);
    if (end == equals + 1 || *end != '\0') {
        fail(EXIT_BAD_USAGE, "the value of '%s' is not a number", argument);
    }
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s FMU_DIR VARIABLES_FILE [NAME=VALUE ...]\n", argc > 0 ? argv[0] : "fmu_host");
        return EXIT_BAD_USAGE;
    }
    const char *fmu_dir = argv[1];
    ModelInfo model = {0};
    read_model_info(argv[2], &model);

    char resource_location[PATH_MAX + 16];
    resources_uri(fmu_dir, resource_location, sizeof resource_location);

    Fmu fmu = {0};
    load_fmu(&fmu, fmu_dir, model.model_identifier);
    printf("fmu model=%s fmiVersion=%s typesPlatform=%s\n", model.model_identifier, fmu.get_version(),
           fmu.get_types_platform());
    /* loggingOn: the host judges its set calls by what is logged (see worst_logged_status). */
    fmu.component = fmu.instantiate("turn_mill_c_host", fmi2CoSimulation, model.guid, resource_location, &CALLBACKS,
                                    fmi2False /* visible */, fmi2True /* loggingOn */);
    if (fmu.component == NULL) {
        fail(EXIT_FMU_FAILED, "fmi2Instantiate failed; the FMU's log above says why");
    }
    fmu.instance_usable = true;
    fmu_to_release = &fmu;
    Host host = {.fmu = &fmu, .model = &model};

    for (int index = 3; index < argc; ++index) {
        char name[256];
        double value;
        parse_parameter(argv[index], name, sizeof name, &value);
        set_real_parameter(&host, name, value);
    }
    double stop_time = START_TIME_S + STEP_COUNT * COMMUNICATION_STEP_S;
    worst_logged_status = fmi2OK;
    check(&fmu, fmu.setup_experiment(fmu.component, fmi2False, 0.0, START_TIME_S, fmi2True, stop_time),
          "fmi2SetupExperiment");
    check(&fmu, fmu.enter_initialization_mode(fmu.component), "fmi2EnterInitializationMode");
    check(&fmu, fmu.exit_initialization_mode(fmu.component), "fmi2ExitInitializationMode");
    printf("initialized t=%.17g\n", START_TIME_S);

    run(&host);

    worst_logged_status = fmi2OK;
    check(&fmu, fmu.terminate(fmu.component), "fmi2Terminate");
    fmu_to_release = NULL;
    release_fmu(&fmu);
    printf("done\n");
    free_model_info(&model);
    return EXIT_SUCCESS;
}
