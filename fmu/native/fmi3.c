/*
 * fmi3.c - the FMI 3.0 co-simulation entry points of the VC harness FMU, a front end on the NC
 * worker (worker_link.h), with the same variables as FMI 2.0: Float64, Int32 and Boolean.  The FMI
 * headers in include/ are the Modelica Association's (2-clause BSD licence, in each file).
 *
 * Co-simulation with a fixed communication step: no event mode, no clocks, no early return.  The
 * functions of model exchange, scheduled execution, clocks, states and derivatives answer
 * fmi3Error (fmi3Instantiate... for them returns NULL) with a message that says so.
 */
#define _DEFAULT_SOURCE

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "worker_link.h"

typedef struct {
    VcWorker *worker;
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
} Instance;

static void log_to_host(void *context, VcStatus status, const char *category, const char *message)
{
    Instance *instance = context;
    if (instance->log_message != NULL) {
        instance->log_message(instance->environment, (fmi3Status)status, category, message);
    }
}

static fmi3Status unsupported(fmi3Instance instance, const char *function)
{
    char message[256];
    snprintf(message, sizeof message, "%s: the VC harness FMU does not provide this function", function);
    if (instance != NULL) {
        vc_log(((Instance *)instance)->worker, VC_ERROR, message);
    }
    return fmi3Error;
}

/* ------------------------------------------------------------------------ instance */
FMI3_Export const char *fmi3GetVersion(void) { return fmi3Version; }

FMI3_Export fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible,
    fmi3Boolean loggingOn, fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
    const fmi3ValueReference requiredIntermediateVariables[], size_t nRequiredIntermediateVariables,
    fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage,
    fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)visible;
    (void)earlyReturnAllowed; /* steps never return early */
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    Instance *instance = calloc(1, sizeof *instance);
    if (instance == NULL) {
        return NULL;
    }
    instance->environment = instanceEnvironment;
    instance->log_message = logMessage;
    if (eventModeUsed) {
        log_to_host(instance, VC_ERROR, "logStatusError",
                    "this FMU has no event mode (no clocks, no events): instantiate it with eventModeUsed = false");
    } else if (resourcePath == NULL) {
        log_to_host(instance, VC_ERROR, "logStatusError", "fmi3InstantiateCoSimulation needs the resource path");
    } else {
        instance->worker = vc_worker_start(resourcePath, instanceName, instantiationToken, 3, loggingOn,
                                           log_to_host, instance);
    }
    if (instance->worker == NULL) {
        free(instance);
        return NULL;
    }
    return instance;
}

FMI3_Export void fmi3FreeInstance(fmi3Instance instance)
{
    if (instance != NULL) {
        vc_worker_stop(((Instance *)instance)->worker);
        free(instance);
    }
}

FMI3_Export fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                                           const fmi3String categories[])
{
    (void)nCategories;
    (void)categories;
    vc_set_logging(((Instance *)instance)->worker, loggingOn);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                                   fmi3Float64 tolerance, fmi3Float64 startTime,
                                                   fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    VcWorker *worker = ((Instance *)instance)->worker;
    VcStatus status = vc_setup(worker, startTime);
    return (fmi3Status)(status >= VC_ERROR ? status : vc_enter_initialization(worker));
}

FMI3_Export fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    return (fmi3Status)vc_exit_initialization(((Instance *)instance)->worker);
}

FMI3_Export fmi3Status fmi3Terminate(fmi3Instance instance)
{
    return (fmi3Status)vc_terminate(((Instance *)instance)->worker);
}

FMI3_Export fmi3Status fmi3Reset(fmi3Instance instance) { return (fmi3Status)vc_reset(((Instance *)instance)->worker); }

FMI3_Export fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                                  fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                  fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                                  fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    VcStatus status = vc_do_step(((Instance *)instance)->worker, currentCommunicationPoint, communicationStepSize);
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    /* a refused step leaves the NC where it stood */
    *lastSuccessfulTime = currentCommunicationPoint + (status == VC_OK || status == VC_WARNING ? communicationStepSize : 0.0);
    return (fmi3Status)status;
}

/* ------------------------------------------------------------------------ values */
static fmi3Status count_mismatch(fmi3Instance instance, size_t references, size_t values)
{
    char message[160];
    snprintf(message, sizeof message, "%zu values for %zu value references: every variable of this FMU is a scalar",
             values, references);
    vc_log(((Instance *)instance)->worker, VC_ERROR, message);
    return fmi3Error;
}

/* Every variable of this FMU is a scalar: as many values as value references. */
#define CHECK_COUNTS()                                                                                  \
    do {                                                                                                \
        if (nValues != nValueReferences) {                                                              \
            return count_mismatch(instance, nValueReferences, nValues);                                 \
        }                                                                                               \
    } while (0)

FMI3_Export fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                      size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_get(((Instance *)instance)->worker, VC_REAL, valueReferences, nValueReferences, values);
}

FMI3_Export fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                      size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_set(((Instance *)instance)->worker, VC_REAL, valueReferences, nValueReferences, values);
}

FMI3_Export fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_get_ints(((Instance *)instance)->worker, VC_INTEGER, valueReferences, nValues, values);
}

FMI3_Export fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                      size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_get_bools(((Instance *)instance)->worker, valueReferences, nValues, values);
}

FMI3_Export fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_set_ints(((Instance *)instance)->worker, VC_INTEGER, valueReferences, nValues, values);
}

FMI3_Export fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                      size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    CHECK_COUNTS();
    return (fmi3Status)vc_set_bools(((Instance *)instance)->worker, valueReferences, nValues, values);
}

/* ------------------------------------------------------------------------ what this FMU does not do
 * (the parameters are unused: each answers fmi3Error, or NULL for another kind of instance) */
#pragma GCC diagnostic ignored "-Wunused-parameter"

FMI3_Export fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
    fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage)
{ return NULL; /* co-simulation only */ }

FMI3_Export fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
    fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate, fmi3LockPreemptionCallback lockPreemption,
    fmi3UnlockPreemptionCallback unlockPreemption)
{ return NULL; /* co-simulation only */ }

FMI3_Export fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{ return unsupported(instance, "fmi3EnterEventMode"); }

FMI3_Export fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Float32 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetFloat32"); }

FMI3_Export fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Int8 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetInt8"); }

FMI3_Export fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3UInt8 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetUInt8"); }

FMI3_Export fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Int16 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetInt16"); }

FMI3_Export fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3UInt16 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetUInt16"); }

FMI3_Export fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3UInt32 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetUInt32"); }

FMI3_Export fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Int64 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetInt64"); }

FMI3_Export fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3UInt64 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetUInt64"); }

FMI3_Export fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3String values[], size_t nValues)
{ return unsupported(instance, "fmi3GetString"); }

FMI3_Export fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{ return unsupported(instance, "fmi3GetBinary"); }

FMI3_Export fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Clock values[])
{ return unsupported(instance, "fmi3GetClock"); }

FMI3_Export fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Float32 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetFloat32"); }

FMI3_Export fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Int8 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetInt8"); }

FMI3_Export fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3UInt8 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetUInt8"); }

FMI3_Export fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Int16 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetInt16"); }

FMI3_Export fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3UInt16 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetUInt16"); }

FMI3_Export fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3UInt32 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetUInt32"); }

FMI3_Export fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Int64 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetInt64"); }

FMI3_Export fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3UInt64 values[], size_t nValues)
{ return unsupported(instance, "fmi3SetUInt64"); }

FMI3_Export fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3String values[], size_t nValues)
{ return unsupported(instance, "fmi3SetString"); }

FMI3_Export fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{ return unsupported(instance, "fmi3SetBinary"); }

FMI3_Export fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Clock values[])
{ return unsupported(instance, "fmi3SetClock"); }

FMI3_Export fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
    size_t* nDependencies)
{ return unsupported(instance, "fmi3GetNumberOfVariableDependencies"); }

FMI3_Export fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent, size_t
    elementIndicesOfDependent[], fmi3ValueReference independents[], size_t elementIndicesOfIndependents[],
    fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{ return unsupported(instance, "fmi3GetVariableDependencies"); }

FMI3_Export fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState)
{ return unsupported(instance, "fmi3GetFMUState"); }

FMI3_Export fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{ return unsupported(instance, "fmi3SetFMUState"); }

FMI3_Export fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState)
{ return unsupported(instance, "fmi3FreeFMUState"); }

FMI3_Export fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t* size)
{ return unsupported(instance, "fmi3SerializedFMUStateSize"); }

FMI3_Export fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
    size_t size)
{ return unsupported(instance, "fmi3SerializeFMUState"); }

FMI3_Export fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
    fmi3FMUState* FMUState)
{ return unsupported(instance, "fmi3DeserializeFMUState"); }

FMI3_Export fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t
    nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64
    sensitivity[], size_t nSensitivity)
{ return unsupported(instance, "fmi3GetDirectionalDerivative"); }

FMI3_Export fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t
    nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64
    sensitivity[], size_t nSensitivity)
{ return unsupported(instance, "fmi3GetAdjointDerivative"); }

FMI3_Export fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{ return unsupported(instance, "fmi3EnterConfigurationMode"); }

FMI3_Export fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{ return unsupported(instance, "fmi3ExitConfigurationMode"); }

FMI3_Export fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
    size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{ return unsupported(instance, "fmi3GetIntervalDecimal"); }

FMI3_Export fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
    size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
{ return unsupported(instance, "fmi3GetIntervalFraction"); }

FMI3_Export fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3Float64 shifts[])
{ return unsupported(instance, "fmi3GetShiftDecimal"); }

FMI3_Export fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{ return unsupported(instance, "fmi3GetShiftFraction"); }

FMI3_Export fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
    size_t nValueReferences, const fmi3Float64 intervals[])
{ return unsupported(instance, "fmi3SetIntervalDecimal"); }

FMI3_Export fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
    size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{ return unsupported(instance, "fmi3SetIntervalFraction"); }

FMI3_Export fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3Float64 shifts[])
{ return unsupported(instance, "fmi3SetShiftDecimal"); }

FMI3_Export fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t
    nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{ return unsupported(instance, "fmi3SetShiftFraction"); }

FMI3_Export fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{ return unsupported(instance, "fmi3EvaluateDiscreteStates"); }

FMI3_Export fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
    fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged, fmi3Boolean*
    valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime)
{ return unsupported(instance, "fmi3UpdateDiscreteStates"); }

FMI3_Export fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{ return unsupported(instance, "fmi3EnterContinuousTimeMode"); }

FMI3_Export fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean
    noSetFMUStatePriorToCurrentPoint, fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation)
{ return unsupported(instance, "fmi3CompletedIntegratorStep"); }

FMI3_Export fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{ return unsupported(instance, "fmi3SetTime"); }

FMI3_Export fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t
    nContinuousStates)
{ return unsupported(instance, "fmi3SetContinuousStates"); }

FMI3_Export fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t
    nContinuousStates)
{ return unsupported(instance, "fmi3GetContinuousStateDerivatives"); }

FMI3_Export fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t
    nEventIndicators)
{ return unsupported(instance, "fmi3GetEventIndicators"); }

FMI3_Export fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t
    nContinuousStates)
{ return unsupported(instance, "fmi3GetContinuousStates"); }

FMI3_Export fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t
    nContinuousStates)
{ return unsupported(instance, "fmi3GetNominalsOfContinuousStates"); }

FMI3_Export fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators)
{ return unsupported(instance, "fmi3GetNumberOfEventIndicators"); }

FMI3_Export fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates)
{ return unsupported(instance, "fmi3GetNumberOfContinuousStates"); }

FMI3_Export fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{ return unsupported(instance, "fmi3EnterStepMode"); }

FMI3_Export fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues)
{ return unsupported(instance, "fmi3GetOutputDerivatives"); }

FMI3_Export fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
    fmi3Float64 activationTime)
{ return unsupported(instance, "fmi3ActivateModelPartition"); }
