// A minimal FMI 3.0 co-simulation master for relnav3.fmu, on its own declarations
// (fmi3_minimal.hpp) and its own modelDescription.xml reader. It dlopen()s
// binaries/x86_64-linux/<modelIdentifier>.so, sets the parameters and the array inputs
// (thrust[3], measurement[3]) and reads the array outputs (position[3], velocity[3],
// sigma[6], covariance[36]) while running paper 000's example second by second. Checked:
// the outputs equal the C ABI's for the same truth and noise (to 1e-9 relative, as the FMI
// 2.0 master's) and meet the same accuracy bar against this harness's own truth; the
// covariance is symmetric, positive definite (a Cholesky factorisation written here) and
// its diagonal's square root is sigma, bit for bit; a serialised FMU state continues bit for
// bit; a wrong instantiation token is refused (null), a step before initialisation and
// fmi3EnterEventMode in an instance made without eventModeUsed return fmi3Error with a
// logged reason.

#include "capi_runner.hpp"
#include "check.hpp"
#include "fmi3_minimal.hpp"
#include "model_description.hpp"
#include "scenario.hpp"
#include "shared_object.hpp"

#include <relnav.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef RELNAV_FMU3_DIR
#error "RELNAV_FMU3_DIR (the unpacked FMI 3.0 FMU directory) must be defined"
#endif

using namespace harness;

namespace {

constexpr int kFullRuns = 20;
constexpr double kRelTol = 1e-9;

struct Log {
    std::vector<std::string> messages;
};

extern "C" void log_message(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                            fmi3String message) {
    Log* log = static_cast<Log*>(env);
    const std::string text = std::string(category ? category : "<null>") + " [" + std::to_string(status) +
                             "] " + (message ? message : "");
    if (log) log->messages.push_back(text);
}

#define RELNAV_FMI3_FUNCTIONS(X)                                                                          \
    X(fmi3GetVersion) X(fmi3InstantiateCoSimulation) X(fmi3FreeInstance) X(fmi3EnterInitializationMode)   \
    X(fmi3ExitInitializationMode) X(fmi3EnterEventMode) X(fmi3Terminate) X(fmi3Reset) X(fmi3GetFloat64)   \
    X(fmi3SetFloat64) X(fmi3SetInt32) X(fmi3SetBoolean) X(fmi3GetFMUState) X(fmi3SetFMUState)             \
    X(fmi3FreeFMUState) X(fmi3SerializedFMUStateSize) X(fmi3SerializeFMUState)                           \
    X(fmi3DeserializeFMUState) X(fmi3DoStep)

struct Fmi3Api {
#define RELNAV_DECLARE(name) name##TYPE* name = nullptr;
    RELNAV_FMI3_FUNCTIONS(RELNAV_DECLARE)
#undef RELNAV_DECLARE
};

class Library {
public:
    explicit Library(const std::string& path) : so_(path) {
#define RELNAV_RESOLVE(name)                                                       \
    {                                                                              \
        void* sym = so_.symbol(#name);                                             \
        if (!sym) throw std::runtime_error("the FMU does not export " #name);      \
        std::memcpy(&api.name, &sym, sizeof sym);                                  \
    }
        RELNAV_FMI3_FUNCTIONS(RELNAV_RESOLVE)
#undef RELNAV_RESOLVE
    }

private:
    SharedObject so_;

public:
    Fmi3Api api;
};

struct Master {
    const Fmi3Api& api;
    const ModelDescription3& md;
    Log& log;

    fmi3Instance instantiate(const std::string& token, bool event_mode = false) const {
        return api.fmi3InstantiateCoSimulation("fmu3_master", token.c_str(), nullptr, false, false, event_mode,
                                               false, nullptr, 0, &log, log_message, nullptr);
    }
    fmi3ValueReference vr(const std::string& name) const { return md.at(name).value_reference; }
    void set_int(fmi3Instance c, const char* name, int v) const {
        const fmi3ValueReference r = vr(name);
        const fmi3Int32 x = v;
        CHECK_MSG(api.fmi3SetInt32(c, &r, 1, &x, 1) == fmi3::OK, name);
    }
    void set_real(fmi3Instance c, const char* name, double v) const {
        const fmi3ValueReference r = vr(name);
        CHECK_MSG(api.fmi3SetFloat64(c, &r, 1, &v, 1) == fmi3::OK, name);
    }
};

// Every parameter from the C ABI's configuration for `filter`, then initialise.
void initialise(const Master& m, fmi3Instance c, int filter, double stop_time) {
    const relnav_config cfg = scenario_config(filter);
    m.set_int(c, "filter", cfg.filter);
    m.set_int(c, "frame", cfg.frame);
    m.set_int(c, "discretization", cfg.discretization);
    m.set_int(c, "seed", static_cast<int>(cfg.seed));
    const std::pair<const char*, double> reals[] = {
        {"mean_motion", cfg.mean_motion}, {"chaser_mass", cfg.chaser_mass}, {"sigma_range", cfg.sigma_range},
        {"sigma_angle", cfg.sigma_angle}, {"x0", cfg.x0[0]},                {"y0", cfg.x0[1]},
        {"z0", cfg.x0[2]},                {"vx0", cfg.x0[3]},               {"vy0", cfg.x0[4]},
        {"vz0", cfg.x0[5]},               {"sigma_pos0", cfg.sigma_pos0},   {"sigma_vel0", cfg.sigma_vel0},
        {"accel_psd", cfg.accel_psd},
    };
    for (const auto& kv : reals) m.set_real(c, kv.first, kv.second);
    CHECK(m.api.fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, stop_time) == fmi3::OK);
    CHECK(m.api.fmi3ExitInitializationMode(c) == fmi3::OK);
}

// The lower Cholesky factor exists (a symmetric matrix is positive definite).
bool positive_definite(const double* p) {
    double l[36] = {};
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j <= i; ++j) {
            double s = p[i * 6 + j];
            for (int k = 0; k < j; ++k) s -= l[i * 6 + k] * l[j * 6 + k];
            if (i == j) {
                if (!(s > 0.0)) return false;
                l[i * 6 + i] = std::sqrt(s);
            } else {
                l[i * 6 + j] = s / l[j * 6 + j];
            }
        }
    return true;
}

// One run through the FMU's arrays, steps k0 .. k1-1 (initialised by the caller); checks
// the covariance at every step.
void steps(const Master& m, fmi3Instance c, const Paper000& p, const std::vector<Vec3>& z, int k0, int k1,
           Trace& tr) {
    const fmi3ValueReference thrust = m.vr("thrust"), meas = m.vr("measurement"),
                             valid = m.vr("measurement_valid");
    const fmi3ValueReference outs[] = {m.vr("position"), m.vr("velocity"), m.vr("sigma"), m.vr("covariance")};
    CHECK(m.md.at("covariance").size == 36 && m.md.at("sigma").size == 6);
    const fmi3Boolean yes = true;
    CHECK(m.api.fmi3SetBoolean(c, &valid, 1, &yes, 1) == fmi3::OK);
    double y[48];
    for (int k = k0; k < k1; ++k) {
        const double t = k * p.dt;
        const Vec3 u = p.thrust_at(t);
        fmi3Boolean event = true, terminate = true, early = true;
        double last = -1.0;
        fmi3Status st = m.api.fmi3SetFloat64(c, &thrust, 1, u.data(), 3);
        if (st == fmi3::OK) st = m.api.fmi3SetFloat64(c, &meas, 1, z[static_cast<size_t>(k)].data(), 3);
        if (st == fmi3::OK) st = m.api.fmi3DoStep(c, t, p.dt, true, &event, &terminate, &early, &last);
        if (st == fmi3::OK) st = m.api.fmi3GetFloat64(c, outs, 4, y, 48);
        if (st != fmi3::OK) {
            record_failure(__FILE__, __LINE__, "FMI 3.0 step at t=" + std::to_string(t) + " failed");
            tr.ok = false;
            return;
        }
        CHECK(!event && !terminate && !early && last == t + p.dt);
        Vec6 x{}, s{};
        for (int i = 0; i < 6; ++i) {
            x[static_cast<size_t>(i)] = y[i];
            s[static_cast<size_t>(i)] = y[6 + i];
        }
        const double* cov = y + 12;
        bool symmetric = true, diagonal = true;
        for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < 6; ++j) symmetric = symmetric && cov[i * 6 + j] == cov[j * 6 + i];
            diagonal = diagonal && std::sqrt(cov[i * 6 + i]) == s[static_cast<size_t>(i)];
        }
        CHECK_MSG(symmetric && diagonal && positive_definite(cov),
                  "covariance at t=" + std::to_string(t) + ": symmetric, sqrt(diagonal) = sigma, positive definite");
        tr.state.push_back(x);
        tr.sigma.push_back(s);
    }
}

void accuracy_and_equivalence(const Master& m, int runs) {
    std::printf("\nFMI 3.0 FMU vs C ABI, paper 000's example\n");
    print_table_header();
    const Paper000 plain;
    const Paper000 burn = paper000_with_burn();
    struct Case {
        const char* name;
        const Paper000* p;
        int filter;
    };
    const Case cases[] = {{"FMU3 EKF", &plain, RELNAV_FILTER_EKF},
                          {"FMU3 UKF burn 100-160s", &burn, RELNAV_FILTER_UKF},
                          {"FMU3 IMM", &plain, RELNAV_FILTER_IMM}};
    double worst = 0.0;
    for (const Case& cs : cases) {
        const auto truth = truth_trajectory(*cs.p);
        const fmi3Instance c = m.instantiate(m.md.instantiation_token);
        CHECK(c != nullptr);
        if (!c) continue;
        std::vector<Run> est;
        for (int seed = 0; seed < runs; ++seed) {
            if (seed > 0) CHECK(m.api.fmi3Reset(c) == fmi3::OK);
            const auto z = noisy_measurements(*cs.p, truth, static_cast<std::uint64_t>(seed));
            initialise(m, c, cs.filter, cs.p->steps * cs.p->dt);
            Trace fmu;
            steps(m, c, *cs.p, z, 0, cs.p->steps, fmu);
            CHECK(m.api.fmi3Terminate(c) == fmi3::OK);
            const Trace capi = run_capi(*cs.p, z, cs.filter);
            if (!fmu.ok || !capi.ok) break;
            const double rel = max_rel_diff(fmu, capi);
            worst = std::max(worst, rel);
            CHECK_MSG(rel <= kRelTol, std::string(cs.name) + ": FMI 3.0 FMU differs from the C ABI");
            est.push_back(fmu.state);
        }
        m.api.fmi3FreeInstance(c);
        if (static_cast<int>(est.size()) != runs) continue;
        const Bar bar;
        const Stats st = evaluate(est, truth, bar);
        print_table_row(cs.name, st);
        const int f = check_bar(cs.name, st, bar, kFullRuns);
        for (int i = 0; i < f; ++i) record_failure(__FILE__, __LINE__, std::string(cs.name) + ": accuracy bar");
    }
    std::printf("max relative difference FMI 3.0 FMU vs C ABI: %.3g (tolerance %.0e)\n", worst, kRelTol);
}

void state_round_trip(const Master& m) {
    const Paper000 p;
    const auto truth = truth_trajectory(p);
    const auto z = noisy_measurements(p, truth, 7);
    const fmi3Instance a = m.instantiate(m.md.instantiation_token);
    const fmi3Instance b = m.instantiate(m.md.instantiation_token);
    CHECK(a != nullptr && b != nullptr);
    if (!a || !b) return;
    initialise(m, a, RELNAV_FILTER_UKF, p.steps * p.dt);
    initialise(m, b, RELNAV_FILTER_UKF, p.steps * p.dt);
    Trace head, first, second;
    steps(m, a, p, z, 0, 100, head);
    fmi3FMUState s = nullptr;
    size_t size = 0;
    CHECK(m.api.fmi3GetFMUState(a, &s) == fmi3::OK);
    CHECK(m.api.fmi3SerializedFMUStateSize(a, s, &size) == fmi3::OK && size > 0);
    std::vector<fmi3Byte> bytes(size);
    CHECK(m.api.fmi3SerializeFMUState(a, s, bytes.data(), size) == fmi3::OK);
    steps(m, a, p, z, 100, 200, first);
    // another instance continues from the bytes exactly as the first did
    fmi3FMUState t = nullptr;
    CHECK(m.api.fmi3DeserializeFMUState(b, bytes.data(), size, &t) == fmi3::OK);
    CHECK(m.api.fmi3SetFMUState(b, t) == fmi3::OK);
    steps(m, b, p, z, 100, 200, second);
    bool same = first.state.size() == second.state.size();
    for (size_t k = 0; same && k < first.state.size(); ++k)
        same = std::memcmp(first.state[k].data(), second.state[k].data(), sizeof(Vec6)) == 0 &&
               std::memcmp(first.sigma[k].data(), second.sigma[k].data(), sizeof(Vec6)) == 0;
    CHECK_MSG(same, "a deserialised FMI 3.0 state continues bit for bit in another instance");
    CHECK(m.api.fmi3FreeFMUState(a, &s) == fmi3::OK && s == nullptr);
    CHECK(m.api.fmi3FreeFMUState(b, &t) == fmi3::OK && t == nullptr);
    m.api.fmi3FreeInstance(a);
    m.api.fmi3FreeInstance(b);
    std::printf("FMU state: %zu bytes, continued bit for bit in another instance\n", size);
}

void refusals(const Master& m) {
    m.log.messages.clear();
    CHECK(m.instantiate("{not-the-token}") == nullptr);
    const fmi3Instance c = m.instantiate(m.md.instantiation_token);
    CHECK(c != nullptr);
    if (!c) return;
    fmi3Boolean e = false, t = false, r = false;
    double last = 0.0;
    CHECK(m.api.fmi3DoStep(c, 0.0, 1.0, true, &e, &t, &r, &last) == fmi3::Error);
    CHECK(m.api.fmi3Reset(c) == fmi3::OK);
    initialise(m, c, RELNAV_FILTER_EKF, 10.0);
    CHECK(m.api.fmi3EnterEventMode(c) == fmi3::Error);
    m.api.fmi3FreeInstance(c);
    auto logged = [&m](const char* what) {
        for (const std::string& s : m.log.messages)
            if (s.find(what) != std::string::npos) return true;
        return false;
    };
    CHECK_MSG(logged("does not match this binary"), "the wrong token's reason is logged");
    CHECK_MSG(logged("illegal call sequence"), "the early step's reason is logged");
    CHECK_MSG(logged("eventModeUsed = false"), "fmi3EnterEventMode's refusal is logged");
    std::printf("refusals: %zu log messages\n", m.log.messages.size());
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = parse_runs(argc, argv, kFullRuns);
    const std::string dir = RELNAV_FMU3_DIR;
    std::printf("relnav %s, fmu3_master with %d run(s) per case, FMU at %s\n", relnav_version(), runs, dir.c_str());
    try {
        const ModelDescription3 md = read_model_description3(dir + "/modelDescription.xml");
        CHECK(md.fmi_version == "3.0");
        const std::string so = dir + "/binaries/x86_64-linux/" + md.cs_model_identifier + ".so";
        Library lib(so);
        CHECK(std::string(lib.api.fmi3GetVersion()) == "3.0");
        Log log;
        const Master m{lib.api, md, log};
        accuracy_and_equivalence(m, runs);
        state_round_trip(m);
        refusals(m);
    } catch (const std::exception& e) {
        record_failure(__FILE__, __LINE__, std::string("exception: ") + e.what());
    }
    return finish("fmu3_master");
}
