/*
 * fmi2.c - the FMI 2.0 co-simulation entry points of the VC harness FMU, a front end on the NC
 * worker (worker_link.h).  The FMI headers in include/ are the Modelica Association's (2-clause BSD
 * licence, in each file), as FMPy ships them.
 *
 * The model exchange functions are not there: the FMU declares co-simulation only.  The functions
 * a co-simulation FMU must export but this NC cannot do (states, derivatives, strings, asynchronous
 * steps) answer fmi2Error with a message that says so.
 */
#define _DEFAULT_SOURCE

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "worker_link.h"

typedef struct {
    VcWorker *worker;
    fmi2CallbackFunctions callbacks;
    char *instance_name;
} Instance;

static void log_to_host(void *context, VcStatus status, const char *category, const char *message)
{
    Instance *instance = context;
    if (instance->callbacks.logger == NULL) {
        return;
    }
    /* fmi2CallbackLogger takes a printf format: a '%' in the message is doubled */
    size_t length = strlen(message), percents = 0;
    for (const char *c = message; *c; ++c) {
        percents += *c == '%';
    }
    char *escaped = malloc(length + percents + 1);
    if (escaped == NULL) {
        return;
    }
    char *out = escaped;
    for (const char *c = message; *c; ++c) {
        *out++ = *c;
        if (*c == '%') {
            *out++ = '%';
        }
    }
    *out = '\0';
    instance->callbacks.logger(instance->callbacks.componentEnvironment, instance->instance_name, (fmi2Status)status,
                               category, escaped);
    free(escaped);
}

/* fmuResourceLocation is a file URI: file:///path, file:/path or file://localhost/path, percent-encoded. */
static char *resources_path(const char *uri)
{
    if (uri == NULL) {
        return NULL;
    }
    const char *path = uri;
    if (strncmp(path, "file://localhost/", 17) == 0) {
        path += 16;
    } else if (strncmp(path, "file:///", 8) == 0) {
        path += 7;
    } else if (strncmp(path, "file:/", 6) == 0) {
        path += 5;
    }
    char *decoded = malloc(strlen(path) + 1);
    if (decoded == NULL) {
        return NULL;
    }
    char *out = decoded;
    for (const char *c = path; *c; ++c) {
        unsigned int byte;
        if (c[0] == '%' && c[1] && c[2] && sscanf(c + 1, "%2x", &byte) == 1) {
            *out++ = (char)byte;
            c += 2;
        } else {
            *out++ = *c;
        }
    }
    *out = '\0';
    return decoded;
}

/* ------------------------------------------------------------------------ instance */
FMI2_Export const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

FMI2_Export const char *fmi2GetVersion(void) { return fmi2Version; }

FMI2_Export fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                          fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                                          fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)visible;
    Instance *instance = calloc(1, sizeof *instance);
    if (instance == NULL || functions == NULL) {
        free(instance);
        return NULL;
    }
    instance->callbacks = *functions;
    instance->instance_name = strdup(instanceName ? instanceName : "");
    char *resources = resources_path(fmuResourceLocation);
    if (fmuType != fmi2CoSimulation) {
        log_to_host(instance, VC_ERROR, "logStatusError", "this FMU is for co-simulation only");
    } else if (resources == NULL) {
        log_to_host(instance, VC_ERROR, "logStatusError", "fmi2Instantiate needs the FMU's resource location");
    } else if (instance->instance_name != NULL) {
        instance->worker = vc_worker_start(resources, instance->instance_name, fmuGUID, 2, loggingOn != fmi2False,
                                           log_to_host, instance);
    }
    free(resources);
    if (instance->worker == NULL) {
        free(instance->instance_name);
        free(instance);
        return NULL;
    }
    return instance;
}

FMI2_Export void fmi2FreeInstance(fmi2Component c)
{
    Instance *instance = c;
    if (instance == NULL) {
        return;
    }
    vc_worker_stop(instance->worker);
    free(instance->instance_name);
    free(instance);
}

FMI2_Export fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                                           const fmi2String categories[])
{
    (void)nCategories;
    (void)categories;
    vc_set_logging(((Instance *)c)->worker, loggingOn != fmi2False);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                           fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    return (fmi2Status)vc_setup(((Instance *)c)->worker, startTime);
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    return (fmi2Status)vc_enter_initialization(((Instance *)c)->worker);
}

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    return (fmi2Status)vc_exit_initialization(((Instance *)c)->worker);
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) { return (fmi2Status)vc_terminate(((Instance *)c)->worker); }

FMI2_Export fmi2Status fmi2Reset(fmi2Component c) { return (fmi2Status)vc_reset(((Instance *)c)->worker); }

FMI2_Export fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                  fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    return (fmi2Status)vc_do_step(((Instance *)c)->worker, currentCommunicationPoint, communicationStepSize);
}

/* ------------------------------------------------------------------------ values */
FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    return (fmi2Status)vc_get(((Instance *)c)->worker, VC_REAL, vr, nvr, value);
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Integer value[])
{
    return (fmi2Status)vc_get_ints(((Instance *)c)->worker, VC_INTEGER, vr, nvr, value);
}

FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Boolean value[])
{
    return (fmi2Status)vc_get_ints(((Instance *)c)->worker, VC_BOOLEAN, vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[])
{
    return (fmi2Status)vc_set(((Instance *)c)->worker, VC_REAL, vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Integer value[])
{
    return (fmi2Status)vc_set_ints(((Instance *)c)->worker, VC_INTEGER, vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Boolean value[])
{
    return (fmi2Status)vc_set_ints(((Instance *)c)->worker, VC_BOOLEAN, vr, nvr, value);
}

/* ------------------------------------------------------------------------ what this FMU does not do */
static fmi2Status unsupported(fmi2Component c, const char *function)
{
    char message[256];
    snprintf(message, sizeof message, "%s: the VC harness FMU does not provide this function", function);
    if (c != NULL) {
        vc_log(((Instance *)c)->worker, VC_ERROR, message);
    }
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)vr;
    (void)value;
    return nvr == 0 ? fmi2OK : unsupported(c, "fmi2GetString (the FMU has no String variable)");
}

FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2String value[])
{
    (void)vr;
    (void)value;
    return nvr == 0 ? fmi2OK : unsupported(c, "fmi2SetString (the FMU has no String variable)");
}

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    (void)FMUstate;
    return unsupported(c, "fmi2GetFMUstate");
}

FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    (void)FMUstate;
    return unsupported(c, "fmi2SetFMUstate");
}

FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    (void)FMUstate;
    return unsupported(c, "fmi2FreeFMUstate");
}

FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    (void)FMUstate;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                             size_t size)
{
    (void)FMUstate;
    (void)serializedState;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                               fmi2FMUstate *FMUstate)
{
    (void)serializedState;
    (void)size;
    (void)FMUstate;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

FMI2_Export fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                                    size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                                    size_t nKnown, const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown_ref;
    (void)nUnknown;
    (void)vKnown_ref;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

FMI2_Export fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                   const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

FMI2_Export fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                    const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

FMI2_Export fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep (steps are synchronous)"); }

FMI2_Export fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStatus (steps are synchronous)");
}

FMI2_Export fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetRealStatus (steps are synchronous)");
}

FMI2_Export fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetIntegerStatus (steps are synchronous)");
}

FMI2_Export fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetBooleanStatus (steps are synchronous)");
}

FMI2_Export fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStringStatus (steps are synchronous)");
}
