// Test (b): a minimal FMI 2.0 co-simulation master for the relnav FMU. It reads
// modelDescription.xml (GUID, model identifier, value references by name), dlopen()s
// binaries/linux64/<modelIdentifier>.so, resolves every fmi2 function, and runs paper 000's
// example second by second (inputs, fmi2DoStep(t, 1), outputs). The outputs must equal the C
// ABI's for the same seed (same truth, same noise) to 1e-9 relative and meet the same
// accuracy bar. Also: fmi2Reset reproduces a run exactly; FMU state get/set/serialise
// continues bit for bit in the same and in another instance; a wrong GUID is refused;
// an unimplemented filter fails fmi2ExitInitializationMode with a logged reason; a step
// size <= 0 fails fmi2DoStep; the logger is called (through its varargs) on errors.

#include "capi_runner.hpp"
#include "check.hpp"
#include "fmi2_minimal.hpp"
#include "model_description.hpp"
#include "scenario.hpp"
#include "shared_object.hpp"

#include <relnav.h>


#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef RELNAV_FMU_DIR
#error "RELNAV_FMU_DIR (the unpacked FMU directory) must be defined"
#endif

using namespace harness;

namespace {

constexpr int kFullRuns = 20;
constexpr double kRelTol = 1e-9;

// ------------------------------------------------------------------------------ logger --
struct LogRecord {
    std::string instance;
    fmi2Status status;
    std::string category;
    std::string message;
};

struct Environment {
    unsigned magic = 0x52454c4eu;  // checks componentEnvironment is passed through
    std::vector<LogRecord> records;
    int bad_env = 0;
    bool echo = true;
};

extern "C" void master_logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                              fmi2String category, fmi2String message, ...)
    __attribute__((format(printf, 5, 6)));

extern "C" void master_logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                              fmi2String category, fmi2String message, ...) {
    char text[4096];
    va_list ap;
    va_start(ap, message);
    std::vsnprintf(text, sizeof text, message ? message : "", ap);
    va_end(ap);
    Environment* e = static_cast<Environment*>(env);
    if (e == nullptr || e->magic != 0x52454c4eu) {
        std::printf("[fmu log with a bad componentEnvironment] %s\n", text);
        return;
    }
    e->records.push_back({instance ? instance : "<null>", status, category ? category : "<null>", text});
    if (e->echo) std::printf("    [fmu log] %s status=%d %s: %s\n", instance ? instance : "<null>", status,
                             category ? category : "<null>", text);
}

// ---------------------------------------------------------------------- the FMU library --
#define RELNAV_FMI2_FUNCTIONS(X)                                                                              \
    X(fmi2GetTypesPlatform) X(fmi2GetVersion) X(fmi2SetDebugLogging) X(fmi2Instantiate) X(fmi2FreeInstance)   \
    X(fmi2SetupExperiment) X(fmi2EnterInitializationMode) X(fmi2ExitInitializationMode) X(fmi2Terminate)      \
    X(fmi2Reset) X(fmi2GetReal) X(fmi2GetInteger) X(fmi2GetBoolean) X(fmi2GetString) X(fmi2SetReal)           \
    X(fmi2SetInteger) X(fmi2SetBoolean) X(fmi2SetString) X(fmi2GetFMUstate) X(fmi2SetFMUstate)                \
    X(fmi2FreeFMUstate) X(fmi2SerializedFMUstateSize) X(fmi2SerializeFMUstate) X(fmi2DeSerializeFMUstate)     \
    X(fmi2GetDirectionalDerivative) X(fmi2SetRealInputDerivatives) X(fmi2GetRealOutputDerivatives)            \
    X(fmi2DoStep) X(fmi2CancelStep) X(fmi2GetStatus) X(fmi2GetRealStatus) X(fmi2GetIntegerStatus)             \
    X(fmi2GetBooleanStatus) X(fmi2GetStringStatus)

struct Fmi2Api {
#define RELNAV_DECLARE(name) name##TYPE* name = nullptr;
    RELNAV_FMI2_FUNCTIONS(RELNAV_DECLARE)
#undef RELNAV_DECLARE
};

class FmuLibrary {
public:
    explicit FmuLibrary(const std::string& path) : so_(path) {
        int missing = 0;
#define RELNAV_RESOLVE(name)                                                         \
    {                                                                                \
        void* sym = so_.symbol(#name);                                               \
        if (!sym) {                                                                  \
            record_failure(__FILE__, __LINE__, "the FMU does not export " #name);    \
            ++missing;                                                               \
        }                                                                            \
        std::memcpy(&api.name, &sym, sizeof sym);                                    \
    }
        RELNAV_FMI2_FUNCTIONS(RELNAV_RESOLVE)
#undef RELNAV_RESOLVE
        std::printf("resolved %d fmi2 functions from %s (%d missing)\n", 34 - missing, path.c_str(), missing);
        if (missing) throw std::runtime_error("incomplete FMU");
    }

private:
    SharedObject so_;

public:
    Fmi2Api api;
};

// ---------------------------------------------------------------------- one FMU instance --
class Slave {
public:
    Slave(const Fmi2Api& api, const ModelDescription& md, Environment& env, const std::string& name,
          const std::string& resource_uri, const std::string& guid, fmi2Boolean logging_on = fmi2::False,
          fmi2Type type = fmi2::CoSimulation)
        : api_(api), md_(md) {
        callbacks_.logger = master_logger;
        callbacks_.allocateMemory = std::calloc;
        callbacks_.freeMemory = std::free;
        callbacks_.stepFinished = nullptr;
        callbacks_.componentEnvironment = &env;
        c_ = api_.fmi2Instantiate(name.c_str(), type, guid.c_str(), resource_uri.c_str(), &callbacks_,
                                  fmi2::False, logging_on);
    }
    ~Slave() {
        if (c_) api_.fmi2FreeInstance(c_);
    }
    Slave(const Slave&) = delete;
    Slave& operator=(const Slave&) = delete;

    fmi2Component get() const { return c_; }
    unsigned vr(const std::string& name) const { return md_.at(name).value_reference; }

    fmi2Status set_real(const std::string& name, double v) {
        const fmi2ValueReference r = vr(name);
        return api_.fmi2SetReal(c_, &r, 1, &v);
    }
    fmi2Status set_int(const std::string& name, int v) {
        const fmi2ValueReference r = vr(name);
        return api_.fmi2SetInteger(c_, &r, 1, &v);
    }
    fmi2Status set_bool(const std::string& name, bool v) {
        const fmi2ValueReference r = vr(name);
        const fmi2Boolean b = v ? fmi2::True : fmi2::False;
        return api_.fmi2SetBoolean(c_, &r, 1, &b);
    }
    fmi2Status get_reals(const std::vector<fmi2ValueReference>& refs, double* out) {
        return api_.fmi2GetReal(c_, refs.data(), refs.size(), out);
    }

private:
    const Fmi2Api& api_;
    const ModelDescription& md_;
    fmi2CallbackFunctions callbacks_{};
    fmi2Component c_ = nullptr;
};

// ------------------------------------------------------------------------ the master --
struct Context {
    const Fmi2Api* api;
    const ModelDescription* md;
    Environment* env;
    std::string resource_uri;
    std::vector<fmi2ValueReference> out_state, out_sigma;
};

const char* kStateOutputs[6] = {"x", "y", "z", "vx", "vy", "vz"};
const char* kSigmaOutputs[6] = {"sigma_x", "sigma_y", "sigma_z", "sigma_vx", "sigma_vy", "sigma_vz"};

#define EXPECT_FMI(call, expected)                                                                 \
    do {                                                                                           \
        const fmi2Status st_ = (call);                                                             \
        if (st_ != (expected))                                                                     \
            record_failure(__FILE__, __LINE__, std::string(#call) + " returned " + std::to_string(st_) + \
                                                   ", expected " + std::to_string(expected));     \
    } while (0)

// Set every parameter explicitly, from the C ABI's configuration for `filter` (what the
// C-ABI run uses), then setup experiment and initialise. Returns false if any call failed.
// `particles` > 0 sets the particle filters' particle count (otherwise the FMU's default).
bool initialise(Context& cx, Slave& s, int filter, double stop_time, int particles = 0) {
    const relnav_config c = scenario_config(filter);
    const int before = failure_count();
    EXPECT_FMI(s.set_int("filter", c.filter), fmi2::OK);
    if (particles > 0) EXPECT_FMI(s.set_int("particles", particles), fmi2::OK);
    EXPECT_FMI(s.set_int("frame", c.frame), fmi2::OK);
    EXPECT_FMI(s.set_int("discretization", c.discretization), fmi2::OK);
    EXPECT_FMI(s.set_int("seed", static_cast<int>(c.seed)), fmi2::OK);
    const std::pair<const char*, double> reals[] = {
        {"mean_motion", c.mean_motion}, {"chaser_mass", c.chaser_mass}, {"sigma_range", c.sigma_range},
        {"sigma_angle", c.sigma_angle}, {"x0", c.x0[0]},                {"y0", c.x0[1]},
        {"z0", c.x0[2]},                {"vx0", c.x0[3]},               {"vy0", c.x0[4]},
        {"vz0", c.x0[5]},               {"sigma_pos0", c.sigma_pos0},   {"sigma_vel0", c.sigma_vel0},
        {"accel_psd", c.accel_psd},     {"q_pos_x", c.q_pos[0]},        {"q_pos_y", c.q_pos[1]},
        {"q_pos_z", c.q_pos[2]},        {"q_vel_x", c.q_vel[0]},        {"q_vel_y", c.q_vel[1]},
        {"q_vel_z", c.q_vel[2]},        {"ukf_alpha", c.ukf_alpha},     {"ukf_beta", c.ukf_beta},
        {"ukf_kappa", c.ukf_kappa},
    };
    for (const auto& kv : reals) EXPECT_FMI(s.set_real(kv.first, kv.second), fmi2::OK);
    EXPECT_FMI(cx.api->fmi2SetupExperiment(s.get(), fmi2::False, 0.0, 0.0, fmi2::True, stop_time), fmi2::OK);
    EXPECT_FMI(cx.api->fmi2EnterInitializationMode(s.get()), fmi2::OK);
    EXPECT_FMI(cx.api->fmi2ExitInitializationMode(s.get()), fmi2::OK);
    return failure_count() == before;
}

// One run of the scenario on an instantiated (or reset) slave; ends with fmi2Terminate.
Trace run_fmu(Context& cx, Slave& s, const Paper000& p, const std::vector<Vec3>& z, int filter,
              const Gaps& gaps = Gaps{}) {
    Trace tr;
    if (!initialise(cx, s, filter, p.steps * p.dt)) {
        tr.ok = false;
        return tr;
    }
    // Before the first step the outputs are the initial estimate and its sigma.
    const relnav_config c = scenario_config(filter);
    Vec6 x{}, sg{};
    EXPECT_FMI(s.get_reals(cx.out_state, x.data()), fmi2::OK);
    EXPECT_FMI(s.get_reals(cx.out_sigma, sg.data()), fmi2::OK);
    for (int i = 0; i < 6; ++i) {
        CHECK(x[static_cast<size_t>(i)] == c.x0[i]);
        CHECK(sg[static_cast<size_t>(i)] == (i < 3 ? c.sigma_pos0 : c.sigma_vel0));
    }
    const std::vector<fmi2ValueReference> in_thrust = {s.vr("thrust_x"), s.vr("thrust_y"), s.vr("thrust_z")};
    const std::vector<fmi2ValueReference> in_meas = {s.vr("range"), s.vr("azimuth"), s.vr("elevation")};
    const fmi2ValueReference in_valid = s.vr("measurement_valid");
    tr.state.reserve(static_cast<size_t>(p.steps));
    tr.sigma.reserve(static_cast<size_t>(p.steps));
    for (int k = 0; k < p.steps; ++k) {
        const double t = k * p.dt;
        const Vec3 u = p.thrust_at(t);
        const bool valid = gaps.valid_at(t);
        const fmi2Boolean b = valid ? fmi2::True : fmi2::False;
        fmi2Status st = cx.api->fmi2SetReal(s.get(), in_thrust.data(), 3, u.data());
        if (st == fmi2::OK && valid) st = cx.api->fmi2SetReal(s.get(), in_meas.data(), 3, z[static_cast<size_t>(k)].data());
        if (st == fmi2::OK) st = cx.api->fmi2SetBoolean(s.get(), &in_valid, 1, &b);
        if (st == fmi2::OK) st = cx.api->fmi2DoStep(s.get(), t, p.dt, fmi2::True);
        if (st == fmi2::OK) st = s.get_reals(cx.out_state, x.data());
        if (st == fmi2::OK) st = s.get_reals(cx.out_sigma, sg.data());
        if (st != fmi2::OK) {
            record_failure(__FILE__, __LINE__, "FMU step at t=" + std::to_string(t) + " failed with status " + std::to_string(st));
            tr.ok = false;
            return tr;
        }
        tr.state.push_back(x);
        tr.sigma.push_back(sg);
    }
    double last = -1.0;
    EXPECT_FMI(cx.api->fmi2GetRealStatus(s.get(), fmi2::LastSuccessfulTime, &last), fmi2::OK);
    CHECK(std::fabs(last - p.steps * p.dt) < 1e-9);
    EXPECT_FMI(cx.api->fmi2Terminate(s.get()), fmi2::OK);
    return tr;
}

bool identical(const Trace& a, const Trace& b) {
    if (a.state.size() != b.state.size()) return false;
    for (size_t k = 0; k < a.state.size(); ++k)
        if (std::memcmp(a.state[k].data(), b.state[k].data(), sizeof(Vec6)) != 0 ||
            std::memcmp(a.sigma[k].data(), b.sigma[k].data(), sizeof(Vec6)) != 0)
            return false;
    return true;
}

// ------------------------------------------------------------------- model description --
void check_model_description(const ModelDescription& md) {
    std::printf("modelDescription.xml: fmiVersion %s, modelName %s, guid %s, CS modelIdentifier %s, %zu variables\n",
                md.fmi_version.c_str(), md.model_name.c_str(), md.guid.c_str(), md.cs_model_identifier.c_str(),
                md.variables.size());
    CHECK(md.fmi_version == "2.0");
    CHECK(!md.cs_model_identifier.empty());
    struct Expect {
        const char* name;
        const char* type;
        const char* causality;
    };
    std::vector<Expect> expect = {
        {"thrust_x", "Real", "input"},      {"thrust_y", "Real", "input"},     {"thrust_z", "Real", "input"},
        {"range", "Real", "input"},         {"azimuth", "Real", "input"},      {"elevation", "Real", "input"},
        {"measurement_valid", "Boolean", "input"},
        // the codes are FMI Integers (libcosim and Ecos cannot set Enumerations)
        {"filter", "Integer", "parameter"}, {"frame", "Integer", "parameter"},
        {"discretization", "Integer", "parameter"}, {"seed", "Integer", "parameter"},
        {"resampler", "Integer", "parameter"}, {"noise_model", "Integer", "parameter"},
    };
    for (const char* n : kStateOutputs) expect.push_back({n, "Real", "output"});
    for (const char* n : kSigmaOutputs) expect.push_back({n, "Real", "output"});
    for (const char* n : {"mean_motion", "chaser_mass", "sigma_range", "sigma_angle", "x0", "y0", "z0", "vx0", "vy0",
                          "vz0", "sigma_pos0", "sigma_vel0", "accel_psd", "q_pos_x", "q_pos_y", "q_pos_z", "q_vel_x",
                          "q_vel_y", "q_vel_z", "ukf_alpha", "ukf_beta", "ukf_kappa"})
        expect.push_back({n, "Real", "parameter"});
    for (const Expect& e : expect) {
        const ScalarVariable* v = md.find(e.name);
        CHECK_MSG(v != nullptr, std::string("variable missing: ") + e.name);
        if (!v) continue;
        CHECK_MSG(v->type == e.type, std::string(e.name) + " has type " + v->type);
        CHECK_MSG(v->causality == e.causality, std::string(e.name) + " has causality " + v->causality);
    }
    // Value references are unique per base type.
    for (size_t i = 0; i < md.variables.size(); ++i)
        for (size_t j = i + 1; j < md.variables.size(); ++j) {
            const auto& a = md.variables[i];
            const auto& b = md.variables[j];
            const bool same_base = a.type == b.type || (a.type == "Integer" && b.type == "Enumeration") ||
                                   (a.type == "Enumeration" && b.type == "Integer");
            CHECK_MSG(!(same_base && a.value_reference == b.value_reference),
                      a.name + " and " + b.name + " share a value reference");
        }
    // Parameter start values are the C ABI's defaults (paper 000), bit for bit.
    const relnav_config c = relnav_config_default();
    const std::pair<const char*, double> defaults[] = {
        {"mean_motion", c.mean_motion}, {"chaser_mass", c.chaser_mass}, {"sigma_range", c.sigma_range},
        {"sigma_angle", c.sigma_angle}, {"x0", c.x0[0]}, {"y0", c.x0[1]}, {"z0", c.x0[2]}, {"vx0", c.x0[3]},
        {"vy0", c.x0[4]}, {"vz0", c.x0[5]}, {"sigma_pos0", c.sigma_pos0}, {"sigma_vel0", c.sigma_vel0},
        {"accel_psd", c.accel_psd}, {"q_pos_x", c.q_pos[0]}, {"q_pos_y", c.q_pos[1]}, {"q_pos_z", c.q_pos[2]},
        {"q_vel_x", c.q_vel[0]}, {"q_vel_y", c.q_vel[1]}, {"q_vel_z", c.q_vel[2]}, {"ukf_alpha", c.ukf_alpha},
        {"ukf_beta", c.ukf_beta}, {"ukf_kappa", c.ukf_kappa}, {"filter", static_cast<double>(c.filter)},
        {"frame", static_cast<double>(c.frame)}, {"discretization", static_cast<double>(c.discretization)},
        {"seed", static_cast<double>(c.seed)},
    };
    for (const auto& kv : defaults) {
        const ScalarVariable* v = md.find(kv.first);
        if (!v) continue;
        CHECK_MSG(v->has_start, std::string(kv.first) + " has no start value");
        const double start = std::strtod(v->start.c_str(), nullptr);
        CHECK_MSG(start == kv.second, std::string(kv.first) + " start " + v->start + " differs from the C ABI default");
    }
}

// ----------------------------------------------------------------------- the scenarios --
void accuracy_and_equivalence(Context& cx, int runs) {
    std::printf("\nFMU vs C ABI, paper 000's example; error = estimate at t+1 after the step at t minus truth at t+1\n");
    print_table_header();
    const Paper000 plain;
    const Paper000 burn = paper000_with_burn();
    struct Case {
        const char* name;
        const Paper000* p;
        int filter;
    };
    const Case cases[] = {{"FMU EKF", &plain, RELNAV_FILTER_EKF},
                          {"FMU UKF", &plain, RELNAV_FILTER_UKF},
                          {"FMU EKF burn 100-160s", &burn, RELNAV_FILTER_EKF},
                          {"FMU UKF burn 100-160s", &burn, RELNAV_FILTER_UKF},
                          {"FMU AQUKF (gated)", &plain, RELNAV_FILTER_AQUKF},
                          {"FMU IMM", &plain, RELNAV_FILTER_IMM}};
    double worst_rel = 0.0;
    for (const Case& cs : cases) {
        const auto truth = truth_trajectory(*cs.p);
        Slave s(*cx.api, *cx.md, *cx.env, cs.name, cx.resource_uri, cx.md->guid);
        CHECK(s.get() != nullptr);
        if (!s.get()) continue;
        std::vector<Run> est;
        Trace first;
        for (int seed = 0; seed < runs; ++seed) {
            if (seed > 0) EXPECT_FMI(cx.api->fmi2Reset(s.get()), fmi2::OK);  // reuse the instance
            const auto z = noisy_measurements(*cs.p, truth, static_cast<std::uint64_t>(seed));
            const Trace fmu = run_fmu(cx, s, *cs.p, z, cs.filter);
            const Trace capi = run_capi(*cs.p, z, cs.filter);
            if (!fmu.ok || !capi.ok) {
                record_failure(__FILE__, __LINE__, std::string(cs.name) + ": run failed");
                break;
            }
            const double rel = max_rel_diff(fmu, capi);
            worst_rel = std::max(worst_rel, rel);
            CHECK_MSG(rel <= kRelTol, std::string(cs.name) + " seed " + std::to_string(seed) +
                                          ": FMU differs from the C ABI, max rel diff " + std::to_string(rel));
            if (seed == 0) first = fmu;
            est.push_back(fmu.state);
        }
        if (static_cast<int>(est.size()) != runs) continue;
        // fmi2Reset, then the first run again: identical outputs.
        EXPECT_FMI(cx.api->fmi2Reset(s.get()), fmi2::OK);
        const Trace again = run_fmu(cx, s, *cs.p, noisy_measurements(*cs.p, truth, 0), cs.filter);
        CHECK_MSG(identical(first, again), std::string(cs.name) + ": re-run after fmi2Reset differs");

        const Bar bar;
        const Stats st = evaluate(est, truth, bar);
        print_table_row(cs.name, st);
        const int f = check_bar(cs.name, st, bar, kFullRuns);
        for (int i = 0; i < f; ++i) record_failure(__FILE__, __LINE__, std::string(cs.name) + ": accuracy bar");
    }
    std::printf("max relative difference FMU vs C ABI over all runs, states and sigmas: %.3g (tolerance %.0e)\n",
                worst_rel, kRelTol);
}

// Measurement gaps (measurement_valid = false) and a burn: still the same as the C ABI.
void gaps_and_reset_midway(Context& cx) {
    std::printf("\nmeasurement gaps, reset in mid-run\n");
    const Paper000 p = paper000_with_burn();
    const auto truth = truth_trajectory(p);
    const auto z = noisy_measurements(p, truth, 7);
    const Gaps gaps{120.0, 150.0};
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        Slave s(*cx.api, *cx.md, *cx.env, "gaps", cx.resource_uri, cx.md->guid);
        CHECK(s.get() != nullptr);
        if (!s.get()) continue;
        const Trace fmu = run_fmu(cx, s, p, z, filter, gaps);
        const Trace capi = run_capi(p, z, filter, gaps);
        const double rel = max_rel_diff(fmu, capi);
        std::printf("  filter %d, no measurements in [120, 150) s: max rel diff FMU vs C ABI %.3g\n", filter, rel);
        CHECK(fmu.ok && capi.ok && rel <= kRelTol);
        // The gap must be visible: sigma grows while there are no measurements.
        if (fmu.ok) CHECK(fmu.sigma[148][0] > 2.0 * fmu.sigma[118][0]);

        // Reset in the middle of a run (no terminate), then a full run: same as a fresh one.
        EXPECT_FMI(cx.api->fmi2Reset(s.get()), fmi2::OK);
        CHECK(initialise(cx, s, filter, p.steps * p.dt));
        const fmi2ValueReference r = s.vr("thrust_x");
        const double u = 5.0;
        for (int k = 0; k < 50; ++k) {
            EXPECT_FMI(cx.api->fmi2SetReal(s.get(), &r, 1, &u), fmi2::OK);
            EXPECT_FMI(cx.api->fmi2DoStep(s.get(), k * 1.0, 1.0, fmi2::True), fmi2::OK);
        }
        EXPECT_FMI(cx.api->fmi2Reset(s.get()), fmi2::OK);
        const Trace after = run_fmu(cx, s, p, z, filter, gaps);
        CHECK_MSG(identical(after, fmu), "run after a mid-run fmi2Reset differs from a fresh run");
    }
}

// The IMM's mode-probability outputs (imm_mu_1..3, looked up by name) are the C ABI's
// relnav_estimator_get_mode_probabilities after every step, sum to one, and start at the
// stationary distribution of the mode chain; the other filters publish NaN.
void imm_mode_outputs(Context& cx) {
    std::printf("\nIMM mode probabilities\n");
    const Paper000 p = paper000_with_burn();
    const auto truth = truth_trajectory(p);
    const auto z = noisy_measurements(p, truth, 3);
    Slave s(*cx.api, *cx.md, *cx.env, "imm", cx.resource_uri, cx.md->guid);
    CHECK(s.get() != nullptr);
    if (!s.get()) return;
    const std::vector<fmi2ValueReference> mu_out = {s.vr("imm_mu_1"), s.vr("imm_mu_2"), s.vr("imm_mu_3")};
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_IMM}) {
        EXPECT_FMI(cx.api->fmi2Reset(s.get()), fmi2::OK);
        if (!initialise(cx, s, filter, p.steps * p.dt)) return;
        relnav_config c = scenario_config(filter);
        relnav_estimator* e = nullptr;
        CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK);
        if (!e) return;
        double fmu_mu[3] = {0.0, 0.0, 0.0}, capi_mu[3] = {0.0, 0.0, 0.0};
        EXPECT_FMI(s.get_reals(mu_out, fmu_mu), fmi2::OK);
        CHECK(relnav_estimator_get_mode_probabilities(e, capi_mu) == RELNAV_OK);
        if (filter == RELNAV_FILTER_IMM) {
            double w[3], total = 0.0;
            for (int j = 0; j < 3; ++j) total += (w[j] = 1.0 / (1.0 - c.imm_p_stay[j]));
            for (int j = 0; j < 3; ++j)
                CHECK_MSG(std::fabs(fmu_mu[j] - w[j] / total) < 1e-12 && fmu_mu[j] == capi_mu[j],
                          "initial imm_mu_" + std::to_string(j + 1) + " is not the stationary probability");
        }
        const std::vector<fmi2ValueReference> in_thrust = {s.vr("thrust_x"), s.vr("thrust_y"), s.vr("thrust_z")};
        const std::vector<fmi2ValueReference> in_meas = {s.vr("range"), s.vr("azimuth"), s.vr("elevation")};
        const fmi2ValueReference in_valid = s.vr("measurement_valid");
        const fmi2Boolean yes = fmi2::True;
        double worst = 0.0;
        for (int k = 0; k < 200; ++k) {
            const double t = k * p.dt;
            const Vec3 u = p.thrust_at(t);
            EXPECT_FMI(cx.api->fmi2SetReal(s.get(), in_thrust.data(), 3, u.data()), fmi2::OK);
            EXPECT_FMI(cx.api->fmi2SetReal(s.get(), in_meas.data(), 3, z[static_cast<size_t>(k)].data()), fmi2::OK);
            EXPECT_FMI(cx.api->fmi2SetBoolean(s.get(), &in_valid, 1, &yes), fmi2::OK);
            EXPECT_FMI(cx.api->fmi2DoStep(s.get(), t, p.dt, fmi2::True), fmi2::OK);
            CHECK(relnav_estimator_step(e, u.data(), z[static_cast<size_t>(k)].data(), p.dt) == RELNAV_OK);
            EXPECT_FMI(s.get_reals(mu_out, fmu_mu), fmi2::OK);
            CHECK(relnav_estimator_get_mode_probabilities(e, capi_mu) == RELNAV_OK);
            for (int j = 0; j < 3; ++j) {
                if (filter == RELNAV_FILTER_IMM)
                    worst = std::max(worst, std::fabs(fmu_mu[j] - capi_mu[j]));
                else
                    CHECK(std::isnan(fmu_mu[j]) && std::isnan(capi_mu[j]));
            }
            if (filter == RELNAV_FILTER_IMM) CHECK(std::fabs(fmu_mu[0] + fmu_mu[1] + fmu_mu[2] - 1.0) < 1e-12);
        }
        relnav_estimator_free(e);
        EXPECT_FMI(cx.api->fmi2Terminate(s.get()), fmi2::OK);
        if (filter == RELNAV_FILTER_IMM) {
            std::printf("  imm_mu_* vs the C ABI over 200 steps: max |diff| %.3g\n", worst);
            CHECK(worst == 0.0);
        }
    }
}

size_t count_errors(const Environment& env, size_t from) {
    size_t n = 0;
    for (size_t i = from; i < env.records.size(); ++i)
        if (env.records[i].status == fmi2::Error || env.records[i].status == fmi2::Fatal) ++n;
    return n;
}

std::string last_message(const Environment& env) { return env.records.empty() ? "" : env.records.back().message; }

void error_cases(Context& cx) {
    std::printf("\nerror handling\n");
    Environment& env = *cx.env;
    const Fmi2Api& api = *cx.api;

    // Wrong GUID: no instance, and the reason is logged.
    {
        size_t mark = env.records.size();
        std::string wrong = cx.md->guid;
        wrong[wrong.size() / 2] = wrong[wrong.size() / 2] == '0' ? '1' : '0';
        Slave s(api, *cx.md, env, "wrong_guid", cx.resource_uri, wrong);
        CHECK_MSG(s.get() == nullptr, "fmi2Instantiate accepted a wrong GUID");
        CHECK_MSG(count_errors(env, mark) >= 1, "no error logged for a wrong GUID");
        mark = env.records.size();
        Slave e(api, *cx.md, env, "empty_guid", cx.resource_uri, "");
        CHECK_MSG(e.get() == nullptr, "fmi2Instantiate accepted an empty GUID");
        // Model exchange is not offered by this FMU.
        mark = env.records.size();
        Slave me(api, *cx.md, env, "model_exchange", cx.resource_uri, cx.md->guid, fmi2::False, fmi2::ModelExchange);
        CHECK_MSG(me.get() == nullptr, "fmi2Instantiate accepted fmi2ModelExchange");
        CHECK(count_errors(env, mark) >= 1);
    }

    // A filter whose design inputs are refused together (hinf with hinf_period = 1000 s, valid
    // alone but too long for the default orbit; hinf_period = -1 would be refused when set):
    // fmi2ExitInitializationMode fails with a logged reason; after fmi2Reset the instance
    // works again.
    {
        Slave s(api, *cx.md, env, "filter9", cx.resource_uri, cx.md->guid);
        CHECK(s.get() != nullptr);
        if (s.get()) {
            EXPECT_FMI(s.set_int("filter", 9), fmi2::OK);
            EXPECT_FMI(s.set_real("hinf_period", -1.0), fmi2::Error);
            EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
            EXPECT_FMI(s.set_int("filter", 9), fmi2::OK);
            EXPECT_FMI(s.set_real("hinf_period", 1000.0), fmi2::OK);
            EXPECT_FMI(api.fmi2SetupExperiment(s.get(), fmi2::False, 0.0, 0.0, fmi2::False, 0.0), fmi2::OK);
            EXPECT_FMI(api.fmi2EnterInitializationMode(s.get()), fmi2::OK);
            const size_t mark = env.records.size();
            EXPECT_FMI(api.fmi2ExitInitializationMode(s.get()), fmi2::Error);
            CHECK_MSG(count_errors(env, mark) >= 1, "no error logged for filter = 9");
            const std::string m = last_message(env);
            CHECK_MSG(m.find("period") != std::string::npos, "log message does not give the reason: " + m);
            CHECK(env.records.empty() || env.records.back().instance == "filter9");
            CHECK(env.records.empty() || env.records.back().category == "logStatusError");
            // Stepping is refused in the error state.
            EXPECT_FMI(api.fmi2DoStep(s.get(), 0.0, 1.0, fmi2::True), fmi2::Error);
            EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
            CHECK(initialise(cx, s, RELNAV_FILTER_EKF, 10.0));
            for (int k = 0; k < 10; ++k) EXPECT_FMI(api.fmi2DoStep(s.get(), k * 1.0, 1.0, fmi2::True), fmi2::OK);
            EXPECT_FMI(api.fmi2Terminate(s.get()), fmi2::OK);
        }
    }
    // Codes 3 (AQUKF), 4..8 (particle filters), 9 (H-infinity), 10 (IMM) and 11 (robust
    // EKF) initialise; 12 is not a filter code: refused when set.
    for (int code = 3; code <= 12; ++code) {
        Slave s(api, *cx.md, env, "filter" + std::to_string(code), cx.resource_uri, cx.md->guid);
        if (!s.get()) {
            CHECK(s.get() != nullptr);
            continue;
        }
        env.echo = false;
        const size_t mark = env.records.size();
        const fmi2Status set = s.set_int("filter", code);
        fmi2Status exit_st = set;
        if (set == fmi2::OK) {
            EXPECT_FMI(api.fmi2SetupExperiment(s.get(), fmi2::False, 0.0, 0.0, fmi2::False, 0.0), fmi2::OK);
            EXPECT_FMI(api.fmi2EnterInitializationMode(s.get()), fmi2::OK);
            exit_st = api.fmi2ExitInitializationMode(s.get());
        }
        env.echo = true;
        std::printf("  filter=%d: fmi2SetInteger -> %d, fmi2ExitInitializationMode -> %d: %s\n", code, set,
                    set == fmi2::OK ? exit_st : -1, last_message(env).c_str());
        if (code <= 11) {
            CHECK(set == fmi2::OK);
            // every code 3..11 is implemented (AQUKF, particle filters, H-infinity, IMM, REKF).
            CHECK_MSG(exit_st == fmi2::OK, "filter " + std::to_string(code) + ": " + last_message(env));
        } else {
            CHECK(set == fmi2::Error);
        }
        if (exit_st != fmi2::OK) CHECK(count_errors(env, mark) >= 1);
    }

    // fmi2DoStep with h <= 0 (and other bad steps): fmi2Error, logged, outputs untouched.
    {
        Slave s(api, *cx.md, env, "bad_steps", cx.resource_uri, cx.md->guid);
        CHECK(s.get() != nullptr);
        if (s.get()) {
            struct BadStep {
                const char* what;
                double t, h;
            };
            const double nan = std::numeric_limits<double>::quiet_NaN();
            const BadStep bad[] = {{"h = 0", 3.0, 0.0},
                                   {"h = -1", 3.0, -1.0},
                                   {"h = -0", 3.0, -0.0},
                                   {"h = NaN", 3.0, nan},
                                   {"h = inf", 3.0, std::numeric_limits<double>::infinity()},
                                   {"t != FMU time", 5.0, 1.0},
                                   {"t + h past stopTime", 3.0, 100.0}};
            for (const BadStep& b : bad) {
                EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
                CHECK(initialise(cx, s, RELNAV_FILTER_EKF, 10.0));
                for (int k = 0; k < 3; ++k) EXPECT_FMI(api.fmi2DoStep(s.get(), k * 1.0, 1.0, fmi2::True), fmi2::OK);
                Vec6 before{}, after{};
                EXPECT_FMI(s.get_reals(cx.out_state, before.data()), fmi2::OK);
                const size_t mark = env.records.size();
                const fmi2Status st = api.fmi2DoStep(s.get(), b.t, b.h, fmi2::True);
                std::printf("  fmi2DoStep(%s) -> %d\n", b.what, st);
                CHECK_MSG(st == fmi2::Error, std::string("fmi2DoStep(") + b.what + ") returned " + std::to_string(st));
                CHECK_MSG(count_errors(env, mark) >= 1, std::string("no error logged for fmi2DoStep(") + b.what + ")");
                EXPECT_FMI(s.get_reals(cx.out_state, after.data()), fmi2::OK);  // getters work in the error state
                CHECK(std::memcmp(before.data(), after.data(), sizeof before) == 0);
            }
            // Non-finite inputs reach the estimator and are refused there.
            EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
            CHECK(initialise(cx, s, RELNAV_FILTER_EKF, 10.0));
            size_t mark = env.records.size();
            EXPECT_FMI(s.set_real("thrust_y", std::numeric_limits<double>::quiet_NaN()), fmi2::OK);
            EXPECT_FMI(api.fmi2DoStep(s.get(), 0.0, 1.0, fmi2::True), fmi2::Error);
            CHECK(count_errors(env, mark) >= 1);
            // Outputs cannot be written; unknown value references are refused.
            EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
            CHECK(initialise(cx, s, RELNAV_FILTER_EKF, 10.0));
            mark = env.records.size();
            EXPECT_FMI(s.set_real("x", 1.0), fmi2::Error);
            CHECK(count_errors(env, mark) >= 1);
            EXPECT_FMI(api.fmi2Reset(s.get()), fmi2::OK);
            CHECK(initialise(cx, s, RELNAV_FILTER_EKF, 10.0));
            const fmi2ValueReference unknown = 999999;
            double v = 0.0;
            EXPECT_FMI(api.fmi2GetReal(s.get(), &unknown, 1, &v), fmi2::Error);
            // Calls on a null instance fail without crashing.
            EXPECT_FMI(api.fmi2DoStep(nullptr, 0.0, 1.0, fmi2::True), fmi2::Error);
            api.fmi2FreeInstance(nullptr);
        }
    }
}

// Steps from..to-1 of `p` on an initialised slave; state and sigma after each appended to `out`.
bool fmu_steps(Context& cx, Slave& s, const Paper000& p, const std::vector<Vec3>& z, int from, int to,
               std::vector<double>* out) {
    const std::vector<fmi2ValueReference> in_thrust = {s.vr("thrust_x"), s.vr("thrust_y"), s.vr("thrust_z")};
    const std::vector<fmi2ValueReference> in_meas = {s.vr("range"), s.vr("azimuth"), s.vr("elevation")};
    const fmi2ValueReference in_valid = s.vr("measurement_valid");
    for (int k = from; k < to; ++k) {
        const double t = k * p.dt;
        const Vec3 u = p.thrust_at(t);
        const fmi2Boolean b = (k % 7 == 5) ? fmi2::False : fmi2::True;
        fmi2Status st = cx.api->fmi2SetReal(s.get(), in_thrust.data(), 3, u.data());
        if (st == fmi2::OK) st = cx.api->fmi2SetReal(s.get(), in_meas.data(), 3, z[static_cast<size_t>(k)].data());
        if (st == fmi2::OK) st = cx.api->fmi2SetBoolean(s.get(), &in_valid, 1, &b);
        if (st == fmi2::OK) st = cx.api->fmi2DoStep(s.get(), t, p.dt, fmi2::False);
        Vec6 x{}, sg{};
        if (st == fmi2::OK) st = s.get_reals(cx.out_state, x.data());
        if (st == fmi2::OK) st = s.get_reals(cx.out_sigma, sg.data());
        if (st != fmi2::OK) {
            record_failure(__FILE__, __LINE__, "FMU step at t=" + std::to_string(t) + ": status " + std::to_string(st));
            return false;
        }
        out->insert(out->end(), x.begin(), x.end());
        out->insert(out->end(), sg.begin(), sg.end());
    }
    return true;
}

bool contains(const std::string& s, const char* what) { return s.find(what) != std::string::npos; }

// FMU state, for every filter code: fmi2GetFMUstate mid-run; fmi2SetFMUstate in the same
// instance and, through fmi2SerializeFMUstate / fmi2DeSerializeFMUstate, in a second
// instance that was only instantiated (the parameters come with the state). Both
// continuations must be bit-identical to the uninterrupted run. Truncated or corrupted
// bytes and another instance's state pointer are refused with a logged reason.
// `particles`: the particle filters' count (the reduced valgrind run uses fewer; the round
// trip is the same code whatever the count).
void fmu_state(Context& cx, int particles, bool quick) {
    std::printf("\nFMU state (get, set, serialise, deserialise), %d particles\n", particles);
    const Fmi2Api& api = *cx.api;
    Environment& env = *cx.env;
    Paper000 p = paper000_with_burn();
    p.steps = 30;
    p.burn_start = 5.0;
    p.burn_end = 12.0;
    p.burn_thrust = {20.0, -10.0, 5.0};
    const auto truth = truth_trajectory(p);
    const auto z = noisy_measurements(p, truth, 11);
    const int k0 = 12;
    for (int filter = RELNAV_FILTER_EKF; filter <= RELNAV_FILTER_IMM; ++filter) {
        if (quick && filter == RELNAV_FILTER_HINF) continue;
        Slave a(api, *cx.md, env, "state_a", cx.resource_uri, cx.md->guid);
        Slave b(api, *cx.md, env, "state_b", cx.resource_uri, cx.md->guid);
        if (!a.get() || !b.get()) {
            record_failure(__FILE__, __LINE__, "fmi2Instantiate failed");
            continue;
        }
        env.echo = false;
        std::vector<double> head, tail, again, other;
        const bool ok = initialise(cx, a, filter, p.steps * p.dt, particles) && fmu_steps(cx, a, p, z, 0, k0, &head);
        fmi2FMUstate s = nullptr, s2 = nullptr, s3 = nullptr;
        EXPECT_FMI(api.fmi2GetFMUstate(a.get(), &s), fmi2::OK);
        size_t n = 0;
        EXPECT_FMI(api.fmi2SerializedFMUstateSize(a.get(), s, &n), fmi2::OK);
        std::vector<fmi2Byte> bytes(n);
        EXPECT_FMI(api.fmi2SerializeFMUstate(a.get(), s, bytes.data(), n), fmi2::OK);
        fmu_steps(cx, a, p, z, k0, p.steps, &tail);
        EXPECT_FMI(api.fmi2SetFMUstate(a.get(), s), fmi2::OK);
        fmu_steps(cx, a, p, z, k0, p.steps, &again);
        EXPECT_FMI(api.fmi2DeSerializeFMUstate(b.get(), bytes.data(), n, &s2), fmi2::OK);
        EXPECT_FMI(api.fmi2SetFMUstate(b.get(), s2), fmi2::OK);
        fmu_steps(cx, b, p, z, k0, p.steps, &other);
        const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
            return !x.empty() && x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
        };
        CHECK_MSG(ok && same(again, tail), "filter " + std::to_string(filter) + ": same instance differs");
        CHECK_MSG(ok && same(other, tail), "filter " + std::to_string(filter) + ": another instance differs");
        // refusals, each logged with its reason
        size_t mark = env.records.size();
        EXPECT_FMI(api.fmi2DeSerializeFMUstate(b.get(), bytes.data(), n - 1, &s3), fmi2::Error);
        CHECK(count_errors(env, mark) == 1 && contains(last_message(env), "truncated"));
        std::vector<fmi2Byte> bad = bytes;
        bad[n / 2] = static_cast<fmi2Byte>(bad[n / 2] ^ 0x08);
        mark = env.records.size();
        EXPECT_FMI(api.fmi2DeSerializeFMUstate(b.get(), bad.data(), n, &s3), fmi2::Error);
        CHECK(count_errors(env, mark) == 1 && contains(last_message(env), "checksum mismatch"));
        mark = env.records.size();
        EXPECT_FMI(api.fmi2SetFMUstate(b.get(), s), fmi2::Error);  // a's state pointer
        CHECK(count_errors(env, mark) == 1 && contains(last_message(env), "unknown FMU state"));
        CHECK(s3 == nullptr);
        EXPECT_FMI(api.fmi2FreeFMUstate(a.get(), &s), fmi2::OK);
        EXPECT_FMI(api.fmi2FreeFMUstate(b.get(), &s2), fmi2::OK);
        CHECK(s == nullptr && s2 == nullptr);
        env.echo = true;
        std::printf("  filter %d: state %zu bytes; %d steps after the restore bit-identical: same instance %s, "
                    "another instance %s\n",
                    filter, n, p.steps - k0, same(again, tail) ? "yes" : "NO", same(other, tail) ? "yes" : "NO");
    }
}

// Logging: with loggingOn the FMU reports its initialisation; fmi2SetDebugLogging(false)
// silences everything but errors; instances created with loggingOn = false only log errors.
void logging(Context& cx) {
    std::printf("\nlogging\n");
    Environment& env = *cx.env;
    const Fmi2Api& api = *cx.api;
    {
        Slave s(api, *cx.md, env, "logging", cx.resource_uri, cx.md->guid, fmi2::True);
        CHECK(s.get() != nullptr);
        if (!s.get()) return;
        env.echo = false;
        size_t mark = env.records.size();
        CHECK(initialise(cx, s, RELNAV_FILTER_UKF, 10.0));
        size_t info = 0;
        for (size_t i = mark; i < env.records.size(); ++i) {
            CHECK(env.records[i].instance == "logging");
            if (env.records[i].status == fmi2::OK && !env.records[i].message.empty()) ++info;
        }
        env.echo = true;
        std::printf("  loggingOn = true: %zu messages during set-up, e.g. \"%s\"\n", env.records.size() - mark,
                    last_message(env).c_str());
        CHECK_MSG(info >= 1, "no informational message with loggingOn = true");
        EXPECT_FMI(api.fmi2SetDebugLogging(s.get(), fmi2::False, 0, nullptr), fmi2::OK);
        mark = env.records.size();
        EXPECT_FMI(api.fmi2DoStep(s.get(), 0.0, 1.0, fmi2::True), fmi2::OK);
        CHECK_MSG(env.records.size() == mark, "messages logged after fmi2SetDebugLogging(false)");
        EXPECT_FMI(api.fmi2DoStep(s.get(), 1.0, 0.0, fmi2::True), fmi2::Error);  // errors still reported
        CHECK(count_errors(env, mark) == 1);
    }
    size_t non_error = 0;
    for (const LogRecord& r : env.records)
        if (r.instance != "logging" && r.status < fmi2::Error) ++non_error;
    CHECK_MSG(non_error == 0, std::to_string(non_error) + " non-error message(s) from instances with loggingOn = false");
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = parse_runs(argc, argv, kFullRuns);
    std::string dir = RELNAV_FMU_DIR;  // the unpacked FMU; --fmu-dir DIR overrides
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--fmu-dir") == 0) dir = argv[i + 1];
    // --quick (the valgrind run): the state round trip without the H-infinity filter, whose
    // LMI design is most of that run's time; the plain and ASan+UBSan runs cover it
    bool quick = false;
    for (int i = 1; i < argc; ++i) quick = quick || std::strcmp(argv[i], "--quick") == 0;
    std::printf("relnav %s, fmu_master with %d run(s) per case, FMU at %s\n", relnav_version(), runs, dir.c_str());
    try {
        const ModelDescription md = read_model_description(dir + "/modelDescription.xml");
        check_model_description(md);
        const std::string so = dir + "/binaries/linux64/" + md.cs_model_identifier + ".so";
        FmuLibrary lib(so);
        CHECK(std::string(lib.api.fmi2GetVersion()) == "2.0");
        CHECK(std::string(lib.api.fmi2GetTypesPlatform()) == "default");

        Environment env;
        Context cx{&lib.api, &md, &env, "file://" + dir, {}, {}};
        for (const char* n : kStateOutputs) cx.out_state.push_back(md.at(n).value_reference);
        for (const char* n : kSigmaOutputs) cx.out_sigma.push_back(md.at(n).value_reference);

        env.echo = true;
        accuracy_and_equivalence(cx, runs);
        gaps_and_reset_midway(cx);
        imm_mode_outputs(cx);
        error_cases(cx);
        fmu_state(cx, runs >= kFullRuns ? 1500 : 200, quick);
        logging(cx);
        for (const LogRecord& r : env.records)
            if (r.status >= fmi2::Error && r.message.empty()) record_failure(__FILE__, __LINE__, "empty error log message");
        std::printf("logger called %zu times, %zu with fmi2Error/fmi2Fatal\n", env.records.size(), count_errors(env, 0));
    } catch (const std::exception& e) {
        record_failure(__FILE__, __LINE__, std::string("exception: ") + e.what());
    }
    return finish("fmu_master");
}
