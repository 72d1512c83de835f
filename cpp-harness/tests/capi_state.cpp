// Test (d): saving and restoring an estimator's state through the C ABI
// (relnav_estimator_save / relnav_estimator_restore), for every filter code 1-10, on paper
// 000's example with a burn and a measurement gap (truth and noise from this harness's own
// C++ closed form). A state saved mid-run and restored — into the same estimator and into a
// fresh one — continues bit for bit as the uninterrupted run. The size query, a short
// buffer, truncations at every length, flipped bytes, another configuration and another
// filter are checked against the documented statuses, with a readable relnav_last_error()
// and the estimator unchanged. The header is read here independently of relnav
// (docs/state-format.md: magic, version, filter code, length, CRC-32 computed below).

#include "capi_runner.hpp"
#include "check.hpp"
#include "scenario.hpp"

#include <relnav.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace harness;

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr int kSteps = 40;
constexpr int kSaveAt = 13;

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), bit by bit: an independent check of
// the checksum the header carries.
std::uint32_t crc32(const std::uint8_t* p, size_t n, std::uint32_t crc = 0) {
    crc = ~crc;
    for (size_t i = 0; i < n; ++i) {
        crc ^= p[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

template <class T>
T read_le(const Bytes& b, size_t at) {
    T v{};
    for (size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(b[at + i]) << (8 * i));
    return v;
}

std::string last_error() {
    const char* m = relnav_last_error();
    return m ? m : "<NULL>";
}

Bytes save(const relnav_estimator* e) {
    size_t need = 0;
    CHECK(relnav_estimator_save(e, nullptr, 0, &need) == RELNAV_OK);
    Bytes b(need);
    size_t len = 0;
    CHECK(relnav_estimator_save(e, b.data(), b.size(), &len) == RELNAV_OK);
    CHECK(len == need);
    return b;
}

relnav_estimator* make(int filter, double sigma_range = 0.5) {
    relnav_config c = scenario_config(filter);
    c.sigma_range = sigma_range;
    relnav_estimator* e = nullptr;
    CHECK_MSG(relnav_estimator_new(&c, &e) == RELNAV_OK, last_error());
    return e;
}

// Steps from..to-1 of the scenario; the estimate and sigma after each, appended to `out`.
bool run(relnav_estimator* e, const Paper000& p, const std::vector<Vec3>& z, int from, int to,
         std::vector<double>* out) {
    for (int k = from; k < to; ++k) {
        const double t = k * p.dt;
        const Vec3 u = p.thrust_at(t);
        const double* zk = (k % 7 == 5) ? nullptr : z[static_cast<size_t>(k)].data();
        if (relnav_estimator_step(e, u.data(), zk, p.dt) != RELNAV_OK) {
            record_failure(__FILE__, __LINE__, "step " + std::to_string(k) + ": " + last_error());
            return false;
        }
        Vec6 x{}, s{};
        CHECK(relnav_estimator_get_state(e, x.data()) == RELNAV_OK);
        CHECK(relnav_estimator_get_sigma(e, s.data()) == RELNAV_OK);
        if (out) {
            out->insert(out->end(), x.begin(), x.end());
            out->insert(out->end(), s.begin(), s.end());
        }
    }
    return true;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The estimator's state is unchanged by a refused restore.
void expect_refused(relnav_estimator* e, const Bytes& bad, const std::string& want, const std::string& what) {
    const Bytes before = save(e);
    const relnav_status st = relnav_estimator_restore(e, bad.data(), bad.size());
    CHECK_MSG(st == RELNAV_ERROR_INVALID_STATE, what + ": status " + std::to_string(static_cast<int>(st)));
    const std::string m = last_error();
    CHECK_MSG(m.find(want) != std::string::npos, what + ": message \"" + m + "\" lacks \"" + want + "\"");
    CHECK_MSG(save(e) == before, what + ": a refused state changed the estimator");
}

void one_filter(int filter, const Paper000& p, const std::vector<Vec3>& z) {
    relnav_estimator* a = make(filter);
    relnav_estimator* fresh = make(filter);
    if (!a || !fresh) return;
    run(a, p, z, 0, kSaveAt, nullptr);
    const Bytes saved = save(a);
    std::vector<double> tail, again, other;
    run(a, p, z, kSaveAt, kSteps, &tail);

    // the header, read independently
    CHECK(saved.size() > 32 && std::memcmp(saved.data(), "RELNAVES", 8) == 0);
    CHECK(read_le<std::uint32_t>(saved, 8) == 6);
    CHECK(static_cast<int>(read_le<std::uint32_t>(saved, 12)) == filter);
    CHECK(read_le<std::uint64_t>(saved, 20) == saved.size() - 32);
    const std::uint32_t crc = crc32(saved.data(), 28);
    CHECK(read_le<std::uint32_t>(saved, 28) == crc32(saved.data() + 32, saved.size() - 32, crc));

    // bit-identical continuation in the same and in a fresh estimator
    CHECK(relnav_estimator_restore(a, saved.data(), saved.size()) == RELNAV_OK);
    run(a, p, z, kSaveAt, kSteps, &again);
    CHECK_MSG(same_bits(again, tail), "filter " + std::to_string(filter) + ": same estimator differs");
    CHECK_MSG(relnav_estimator_restore(fresh, saved.data(), saved.size()) == RELNAV_OK, last_error());
    run(fresh, p, z, kSaveAt, kSteps, &other);
    CHECK_MSG(same_bits(other, tail), "filter " + std::to_string(filter) + ": fresh estimator differs");
    std::printf("  filter %d: state %zu bytes, %d steps after the restore bit-identical (same: %s, fresh: %s)\n",
                filter, saved.size(), kSteps - kSaveAt, same_bits(again, tail) ? "yes" : "NO",
                same_bits(other, tail) ? "yes" : "NO");

    // the size depends on the configuration only; a buffer one byte short is refused
    CHECK(save(a).size() == saved.size());
    Bytes small(saved.size() - 1, 0xAB);
    size_t len = 0;
    CHECK(relnav_estimator_save(a, small.data(), small.size(), &len) == RELNAV_ERROR_BUFFER_TOO_SMALL);
    CHECK(len == saved.size());
    CHECK(last_error().find("needs " + std::to_string(saved.size()) + " bytes") != std::string::npos);
    bool untouched = true;
    for (std::uint8_t v : small) untouched = untouched && v == 0xAB;
    CHECK_MSG(untouched, "a short buffer was written to");

    // refusals: truncated (every length up to 4 kB, then a sample), flipped bytes, other
    // configuration, other filter
    int refused = 0;
    for (size_t n = 0; n < saved.size(); n += (n < 4096 ? 1 : 997)) {
        const relnav_status st = relnav_estimator_restore(a, saved.data(), n);
        CHECK_MSG(st == RELNAV_ERROR_INVALID_STATE, "truncated to " + std::to_string(n));
        refused += st == RELNAV_ERROR_INVALID_STATE;
    }
    expect_refused(a, Bytes(saved.begin(), saved.end() - 1), "truncated", "one byte short");
    std::mt19937_64 rng(static_cast<std::uint64_t>(filter));
    for (int i = 0; i < 100; ++i) {
        Bytes c = saved;
        c[rng() % c.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        const relnav_status st = relnav_estimator_restore(a, c.data(), c.size());
        CHECK_MSG(st == RELNAV_ERROR_INVALID_STATE, "a flipped bit was accepted");
        refused += st == RELNAV_ERROR_INVALID_STATE;
    }
    Bytes c = saved;
    c[c.size() - 5] ^= 0x20;
    expect_refused(a, c, "checksum mismatch", "corrupted");
    relnav_estimator* wide = make(filter, 0.6);
    if (wide) {
        expect_refused(wide, saved, "sigma_range = 0.5 in the state, 0.6 in this estimator", "other configuration");
        relnav_estimator_free(wide);
    }
    relnav_estimator* ekf_or_ukf = make(filter == RELNAV_FILTER_EKF ? RELNAV_FILTER_UKF : RELNAV_FILTER_EKF);
    if (ekf_or_ukf) {
        expect_refused(ekf_or_ukf, saved, "the state is for filter " + std::to_string(filter), "other filter");
        relnav_estimator_free(ekf_or_ukf);
    }
    std::printf("    %d bad states refused\n", refused);
    relnav_estimator_free(a);
    relnav_estimator_free(fresh);
}

}  // namespace

int main(int argc, char** argv) {
    // --quick (the valgrind run): one filter of each family (EKF, AQUKF, RPF, IMM), not the
    // H-infinity one, whose LMI design dominates the run time under valgrind; the plain and
    // the ASan+UBSan runs cover every filter
    bool quick = false;
    for (int i = 1; i < argc; ++i) quick = quick || std::strcmp(argv[i], "--quick") == 0;
    Paper000 p = paper000_with_burn();
    p.steps = kSteps;
    p.burn_start = 8.0;
    p.burn_end = 16.0;
    p.burn_thrust = {20.0, -10.0, 5.0};
    const std::vector<Vec6> truth = truth_trajectory(p);
    const std::vector<Vec3> z = noisy_measurements(p, truth, 3);
    std::printf("relnav %s: estimator state through the C ABI, saved at step %d of %d\n", relnav_version(), kSaveAt,
                kSteps);
    for (int filter = RELNAV_FILTER_EKF; filter <= RELNAV_FILTER_IMM; ++filter) {
        const bool family = filter == RELNAV_FILTER_EKF || filter == RELNAV_FILTER_AQUKF ||
                            filter == RELNAV_FILTER_RPF || filter == RELNAV_FILTER_IMM;
        if (!quick || family) one_filter(filter, p, z);
    }

    // null arguments
    size_t len = 0;
    std::uint8_t byte = 0;
    CHECK(relnav_estimator_save(nullptr, nullptr, 0, &len) == RELNAV_ERROR_NULL_POINTER);
    CHECK(relnav_estimator_restore(nullptr, &byte, 1) == RELNAV_ERROR_NULL_POINTER);
    relnav_estimator* e = make(RELNAV_FILTER_EKF);
    if (e) {
        CHECK(relnav_estimator_save(e, nullptr, 0, nullptr) == RELNAV_ERROR_NULL_POINTER);
        CHECK(relnav_estimator_restore(e, nullptr, 10) == RELNAV_ERROR_NULL_POINTER);
        CHECK(last_error().find("buf") != std::string::npos);
        relnav_estimator_free(e);
    }
    CHECK(std::string(relnav_status_string(RELNAV_ERROR_BUFFER_TOO_SMALL)) == "buffer too small");
    CHECK(std::string(relnav_status_string(RELNAV_ERROR_INVALID_STATE)) == "invalid saved state");
    return finish("capi_state");
}
