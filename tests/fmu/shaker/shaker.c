/* The shaker of examples/shaker_coupling.py as an FMI 2.0 Co-Simulation FMU, so that a system
 * simulator can couple it to the plate FMU (tests/fmu/test_omsimulator.py builds it with the C
 * compiler against the official FMI 2.0 headers and runs the two in OMSimulator).
 *
 * The shaker's moving part is a mass m on a suspension of stiffness k and damping c, driven by the
 * coil force F_d(t) = F_0 sin(2 pi f t), carrying the plate's clamp and pushed back by the plate's
 * force on its base F_b (the input `force`, base.mean_force of the plate):
 *
 *     m x'' + c x' + k x = F_d(t) + F_b.
 *
 * A communication step holds F_b constant and integrates by the implicit midpoint rule in substeps
 * of at most 10 us, as the example's Shaker.advance does; the outputs are the position x (the
 * plate's base displacement) and the velocity. Only what a co-simulation master of the plate
 * needs is offered: FMU states, directional derivatives, input derivatives and the status queries
 * answer fmi2Error. */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

/* The value references of modelDescription.xml. */
enum { FORCE, POSITION, VELOCITY, MASS, STIFFNESS, DAMPING, AMPLITUDE, FREQUENCY, COUNT };

#define PI 3.14159265358979323846
/* The longest substep (s). */
#define SUBSTEP 1e-5

typedef struct {
    double value[COUNT];
    double time;
    fmi2CallbackFunctions callbacks;
    char *name;
} Shaker;

static void reset(Shaker *s) {
    memset(s->value, 0, sizeof s->value);
    /* The start values of modelDescription.xml: 60 kg on a 15 Hz suspension damped at 20 %
     * (k = m (2 pi 15 Hz)^2, c = 2 0.2 sqrt(k m), as the example computes them), a 7 kN coil
     * force at 53 Hz. */
    s->value[MASS] = 60.0;
    s->value[STIFFNESS] = 532958.6376588253;
    s->value[DAMPING] = 2261.946710584651;
    s->value[AMPLITUDE] = 7000.0;
    s->value[FREQUENCY] = 53.0;
    s->time = 0.0;
}

static fmi2Status refuse(fmi2Component c, const char *what) {
    Shaker *s = c;
    if (s != NULL && s->callbacks.logger != NULL)
        s->callbacks.logger(s->callbacks.componentEnvironment, s->name, fmi2Error, "logStatusError",
                            "%s is not offered by this FMU", what);
    return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String location,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible,
                              fmi2Boolean logging) {
    (void)location, (void)visible, (void)logging;
    if (type != fmi2CoSimulation || guid == NULL
        || strcmp(guid, "{5a0c7b1e-shaker-plateimpact-test}") != 0)
        return NULL;
    Shaker *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    const char *given = name != NULL ? name : "shaker";
    s->name = malloc(strlen(given) + 1);
    if (s->name == NULL) {
        free(s);
        return NULL;
    }
    memcpy(s->name, given, strlen(given) + 1);
    if (callbacks != NULL)
        s->callbacks = *callbacks;
    reset(s);
    return s;
}

void fmi2FreeInstance(fmi2Component c) {
    Shaker *s = c;
    if (s != NULL) {
        free(s->name);
        free(s);
    }
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String categories[]) {
    (void)c, (void)on, (void)n, (void)categories;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
    ((Shaker *)c)->time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }

fmi2Status fmi2Reset(fmi2Component c) {
    reset(c);
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
    Shaker *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= COUNT)
            return refuse(c, "this value reference");
        value[i] = s->value[vr[i]];
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
    Shaker *s = c;
    for (size_t i = 0; i < n; i++)
        if (vr[i] >= COUNT || vr[i] == POSITION || vr[i] == VELOCITY)
            return refuse(c, "setting this value reference");
    for (size_t i = 0; i < n; i++)
        s->value[vr[i]] = value[i];
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Shaker *s = c;
    double *v = s->value;
    int n = (int)ceil(h / SUBSTEP - 1e-9);
    if (n < 1)
        n = 1;
    double dt = h / n, m = v[MASS], k = v[STIFFNESS], d = v[DAMPING];
    for (int j = 0; j < n; j++) {
        double f = v[AMPLITUDE] * sin(2 * PI * v[FREQUENCY] * (t + (j + 0.5) * dt)) + v[FORCE];
        /* Midpoint velocity of m (v1 - v0) = dt (F - d vm - k (x0 + x1)/2), x1 = x0 + dt vm. */
        double vm = (2 * m * v[VELOCITY] + dt * (f - k * v[POSITION])) / (2 * m + dt * d + 0.5 * k * dt * dt);
        v[POSITION] += dt * vm;
        v[VELOCITY] = 2 * vm - v[VELOCITY];
    }
    s->time = t + h;
    return fmi2OK;
}

/* Integer, Boolean and String variables: this FMU has none. */
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "an Integer variable");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "an Integer variable");
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "a Boolean variable");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "a Boolean variable");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "a String variable");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String value[]) {
    (void)vr, (void)value;
    return n == 0 ? fmi2OK : refuse(c, "a String variable");
}

/* What the FMU does not offer (canGetAndSetFMUstate, providesDirectionalDerivative and
 * canInterpolateInputs are false in its description). */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) { (void)state; return refuse(c, "fmi2GetFMUstate"); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) { (void)state; return refuse(c, "fmi2SetFMUstate"); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) { (void)state; return refuse(c, "fmi2FreeFMUstate"); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    (void)state, (void)size;
    return refuse(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
    (void)state, (void)bytes, (void)size;
    return refuse(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state) {
    (void)bytes, (void)size, (void)state;
    return refuse(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[], size_t nUnknown,
                                        const fmi2ValueReference known[], size_t nKnown,
                                        const fmi2Real seed[], fmi2Real sensitivity[]) {
    (void)unknown, (void)nUnknown, (void)known, (void)nKnown, (void)seed, (void)sensitivity;
    return refuse(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr, (void)n, (void)order, (void)value;
    return refuse(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr, (void)n, (void)order, (void)value;
    return refuse(c, "fmi2GetRealOutputDerivatives");
}
fmi2Status fmi2CancelStep(fmi2Component c) { return refuse(c, "fmi2CancelStep"); }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Status *value) {
    (void)kind, (void)value;
    return refuse(c, "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value) {
    (void)kind, (void)value;
    return refuse(c, "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value) {
    (void)kind, (void)value;
    return refuse(c, "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value) {
    (void)kind, (void)value;
    return refuse(c, "fmi2GetBooleanStatus");
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind kind, fmi2String *value) {
    (void)kind, (void)value;
    return refuse(c, "fmi2GetStringStatus");
}
