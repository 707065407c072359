/*
 * A C host for the PlateImpact FMU (FMI 2.0 Co-Simulation).
 *
 * Runs the forced 35 Hz scene (base sine of 9 mm at 35 Hz between obstacles at -10 and +10 mm,
 * the FMU's defaults otherwise) for 1 s in communication steps of 1 ms, reads the free corners and
 * the discrete energy, saves the FMU state at 0.5 s, restores it, runs the second half again and
 * checks that it repeats bit for bit. Values are printed as C99 hexadecimal floats (%a), exact.
 *
 * One source, two builds (commands in docs/usage.md, "From C"):
 *   - default: loads binaries/linux64/PlateImpact.so of an unzipped FMU with dlopen, as FMU
 *     importers do (binaries/win64/PlateImpact.dll on Windows; -DPLATE_HOST_BINARY='"..."' names
 *     another binary of the FMU, such as binaries/aarch64-linux/PlateImpact.so of the FMI 3.0 FMU,
 *     the same library, which exports the FMI 2.0 functions too);
 *   - -DPLATE_HOST_LINKED: the library is linked at build time (-l:PlateImpact.so, with an rpath).
 * Both take the unzipped FMU's directory as their first argument and include the FMI 2.0 headers
 * of an installed FMI package (fmpy ships them). With --trajectory as second argument the host
 * also prints the outputs at every communication point of the first run ("point" lines), which
 * tests/fmu/test_platforms.py compares across platforms.
 *
 * The value references below are copied from modelDescription.xml; the test
 * tests/fmu/test_c_host.py fails, naming the variable, if any of them no longer matches it. The
 * GUID is read from the unzipped FMU's modelDescription.xml at run time, as importers do: the
 * build derives it from the description's content, so it changes with every new description.
 */
#define _XOPEN_SOURCE 700 /* realpath, dlopen */

#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#ifndef PLATE_HOST_LINKED
#include <dlfcn.h>
#endif

/* The binary loaded with dlopen, relative to the unzipped FMU's directory. */
#ifndef PLATE_HOST_BINARY
#ifdef _WIN32
#define PLATE_HOST_BINARY "binaries/win64/PlateImpact.dll"
#else
#define PLATE_HOST_BINARY "binaries/linux64/PlateImpact.so"
#endif
#endif

/* Value references: name in modelDescription.xml, type, unit. */
enum {
    VR_MATERIAL_POISSON_RATIO = 5,  /* material.poisson_ratio, Real, 1 */
    VR_BASE_AMPLITUDE = 13,         /* base.amplitude, Real, m */
    VR_BASE_FREQUENCY = 14,         /* base.frequency, Real, Hz */
    VR_CORNER1_DISPLACEMENT = 30,   /* corner1.displacement, Real, m */
    VR_CORNER2_DISPLACEMENT = 31,   /* corner2.displacement, Real, m */
    VR_ENERGY_TOTAL = 35,           /* energy.total, Real, J */
};

/* What the host reads after a run: u at (Lx, 0) and (Lx, Ly) (m), and the energy (J). */
#define OUTPUT_COUNT 3
static const fmi2ValueReference output_vrs[OUTPUT_COUNT] = {
    VR_CORNER1_DISPLACEMENT, VR_CORNER2_DISPLACEMENT, VR_ENERGY_TOTAL};
static const char *const output_names[OUTPUT_COUNT] = {
    "corner1.displacement", "corner2.displacement", "energy.total"};

#define STEP_SIZE 1e-3   /* communication step (s): 10 internal steps of 0.1 ms */
#define STEP_COUNT 1000  /* 1 s */

/* The FMI functions this host calls, as pointers: resolved by dlsym or bound by the linker. */
#define FMI2_FUNCTIONS(X)                                                                        \
    X(Instantiate)                                                                               \
    X(FreeInstance)                                                                              \
    X(SetupExperiment)                                                                           \
    X(EnterInitializationMode)                                                                   \
    X(ExitInitializationMode)                                                                    \
    X(Terminate)                                                                                 \
    X(SetReal)                                                                                   \
    X(GetReal)                                                                                   \
    X(DoStep)                                                                                    \
    X(GetFMUstate)                                                                               \
    X(SetFMUstate)                                                                               \
    X(FreeFMUstate)

typedef struct {
#define MEMBER(name) fmi2##name##TYPE *name;
    FMI2_FUNCTIONS(MEMBER)
#undef MEMBER
} Fmi2;

#ifdef PLATE_HOST_LINKED
static const char *const build = "linked";

static int load(const char *fmu_dir, Fmi2 *fmi) {
    (void)fmu_dir;
#define BIND(name) fmi->name = fmi2##name;
    FMI2_FUNCTIONS(BIND)
#undef BIND
    return 0;
}

static void unload(void) {}
#else
static const char *const build = "dlopen";
static void *library;

static int load(const char *fmu_dir, Fmi2 *fmi) {
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/" PLATE_HOST_BINARY, fmu_dir);
    library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        fprintf(stderr, "cannot load %s: %s\n", path, dlerror());
        return -1;
    }
#define LOOKUP(name)                                                                             \
    fmi->name = (fmi2##name##TYPE *)dlsym(library, "fmi2" #name);                                \
    if (!fmi->name) {                                                                            \
        fprintf(stderr, "%s does not export fmi2" #name "\n", path);                             \
        return -1;                                                                               \
    }
    FMI2_FUNCTIONS(LOOKUP)
#undef LOOKUP
    return 0;
}

static void unload(void) {
    if (library) dlclose(library);
}
#endif

/* The FMU reports through this callback; the message is a printf format with its arguments. */
static void logger(fmi2ComponentEnvironment environment, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    static const char *const names[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
    (void)environment;
    fprintf(stderr, "[%s] %s %s: ", instance, status <= fmi2Pending ? names[status] : "?",
            category);
    va_list args;
    va_start(args, message);
    vfprintf(stderr, message, args);
    va_end(args);
    fputc('\n', stderr);
}

/* Stops the host when an FMI call fails; the FMU has already logged why. */
#define CHECK(call)                                                                              \
    do {                                                                                         \
        fmi2Status status_ = (call);                                                             \
        if (status_ > fmi2Warning) {                                                             \
            fprintf(stderr, "%s returned status %d\n", #call, (int)status_);                     \
            exit(EXIT_FAILURE);                                                                  \
        }                                                                                        \
    } while (0)

/* Takes the communication steps from t = first·STEP_SIZE to t = last·STEP_SIZE; with `trace`,
 * prints the outputs after each ("point k y1 y2 y3", exact). The host may restore an earlier state
 * afterwards, so noSetFMUStatePriorToCurrentPoint is fmi2False. */
static void advance(const Fmi2 *fmi, fmi2Component c, int first, int last, int trace) {
    for (int k = first; k < last; k++) {
        CHECK(fmi->DoStep(c, k * STEP_SIZE, STEP_SIZE, fmi2False));
        if (trace) {
            double y[OUTPUT_COUNT];
            CHECK(fmi->GetReal(c, output_vrs, OUTPUT_COUNT, y));
            printf("point %d %a %a %a\n", k + 1, y[0], y[1], y[2]);
        }
    }
}

static void print_outputs(const char *label, const double y[OUTPUT_COUNT]) {
    for (int k = 0; k < OUTPUT_COUNT; k++)
        printf("%s %s %a (%.6g)\n", label, output_names[k], y[k], y[k]);
}

/* Copies the guid attribute of FMU_DIR/modelDescription.xml into `guid` (at most `size` bytes with
 * the NUL); returns 0, or -1 after saying what is wrong. */
static int read_guid(const char *fmu_dir, char *guid, size_t size) {
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/modelDescription.xml", fmu_dir);
    FILE *file = fopen(path, "rb");
    if (!file) {
        perror(path);
        return -1;
    }
    static char text[1 << 20]; /* the description is about 25 kB */
    size_t length = fread(text, 1, sizeof text - 1, file);
    fclose(file);
    text[length] = '\0';
    const char *start = strstr(text, " guid=\"");
    const char *end = start ? strchr(start + 7, '"') : NULL;
    if (!end || (size_t)(end - (start + 7)) >= size) {
        fprintf(stderr, "%s has no guid attribute\n", path);
        return -1;
    }
    memcpy(guid, start + 7, (size_t)(end - (start + 7)));
    guid[end - (start + 7)] = '\0';
    return 0;
}

int main(int argc, char **argv) {
    const int trace = argc == 3 && strcmp(argv[2], "--trajectory") == 0;
    if (argc != 2 && !trace) {
        fprintf(stderr, "usage: %s UNZIPPED_FMU_DIRECTORY [--trajectory]\n", argv[0]);
        return EXIT_FAILURE;
    }
    Fmi2 fmi;
    char guid[64];
    if (read_guid(argv[1], guid, sizeof guid) != 0 || load(argv[1], &fmi) != 0) return EXIT_FAILURE;

    /* fmuResourceLocation is a file URI of the FMU's resources folder (this FMU has none). */
    char directory[PATH_MAX], resources[PATH_MAX + 32];
    if (!realpath(argv[1], directory)) {
        perror(argv[1]);
        return EXIT_FAILURE;
    }
    snprintf(resources, sizeof resources, "file://%s/resources", directory);

    fmi2CallbackFunctions callbacks = {.logger = logger,
                                       .allocateMemory = calloc,
                                       .freeMemory = free,
                                       .stepFinished = NULL,
                                       .componentEnvironment = NULL};
    fmi2Component c = fmi.Instantiate("plate", fmi2CoSimulation, guid, resources,
                                      &callbacks, fmi2False, fmi2False);
    if (!c) {
        fprintf(stderr, "fmi2Instantiate failed\n");
        return EXIT_FAILURE;
    }

    /* A rejected value is an fmi2Error with a message through the logger, and changes nothing. */
    const fmi2ValueReference poisson = VR_MATERIAL_POISSON_RATIO;
    const double bad_poisson = 0.5;
    if (fmi.SetReal(c, &poisson, 1, &bad_poisson) != fmi2Error) {
        fprintf(stderr, "material.poisson_ratio = 0.5 was accepted\n");
        return EXIT_FAILURE;
    }

    /* The forced 35 Hz scene: the FMU's defaults plus the built-in base sine. */
    const fmi2ValueReference base_vrs[2] = {VR_BASE_AMPLITUDE, VR_BASE_FREQUENCY};
    const double base_values[2] = {0.009, 35.0};
    CHECK(fmi.SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, STEP_COUNT * STEP_SIZE));
    CHECK(fmi.SetReal(c, base_vrs, 2, base_values));
    CHECK(fmi.EnterInitializationMode(c));
    CHECK(fmi.ExitInitializationMode(c));

    const int half = STEP_COUNT / 2;
    advance(&fmi, c, 0, half, trace);
    fmi2FMUstate state = NULL;
    CHECK(fmi.GetFMUstate(c, &state));
    advance(&fmi, c, half, STEP_COUNT, trace);
    double final[OUTPUT_COUNT];
    CHECK(fmi.GetReal(c, output_vrs, OUTPUT_COUNT, final));
    print_outputs("final", final);

    /* Back to the saved state: the second half must repeat exactly. */
    CHECK(fmi.SetFMUstate(c, state));
    advance(&fmi, c, half, STEP_COUNT, 0);
    double repeated[OUTPUT_COUNT];
    CHECK(fmi.GetReal(c, output_vrs, OUTPUT_COUNT, repeated));
    print_outputs("restored", repeated);
    const int identical = memcmp(final, repeated, sizeof final) == 0;

    CHECK(fmi.FreeFMUstate(c, &state));
    CHECK(fmi.Terminate(c));
    fmi.FreeInstance(c);
    unload();

    printf("PlateImpact from C (%s): forced 35 Hz, %d steps of %g s to t = %g s: corner1 %+.4f mm, "
           "corner2 %+.4f mm, energy %.4f J; run restored from t = %g s %s\n",
           build, STEP_COUNT, STEP_SIZE, STEP_COUNT * STEP_SIZE, 1e3 * final[0], 1e3 * final[1],
           final[2], half * STEP_SIZE, identical ? "repeats bit for bit" : "DIFFERS");
    return identical ? EXIT_SUCCESS : EXIT_FAILURE;
}
