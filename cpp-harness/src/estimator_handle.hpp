// How the harness makes and ends an estimator: relnav_estimator_new / _free, or, compiled
// with RELNAV_FLIGHT against the flight library (no heap in the library),
// relnav_estimator_init / _deinit in storage this program allocates as
// relnav_estimator_storage says. The tests are otherwise the same program.
#pragma once

#include <relnav.h>

#include <map>
#include <new>

namespace harness {

#ifdef RELNAV_FLIGHT
struct Placed {
    void* storage;
    size_t align;
};
inline std::map<relnav_estimator*, Placed>& placed() {
    static std::map<relnav_estimator*, Placed> m;
    return m;
}
#endif

inline relnav_status estimator_new(const relnav_config* cfg, relnav_estimator** out) {
#ifdef RELNAV_FLIGHT
    size_t size = 0, align = 0;
    const relnav_status st = relnav_estimator_storage(&size, &align);
    if (st != RELNAV_OK) return st;
    void* mem = ::operator new(size, std::align_val_t(align));
    const relnav_status made = relnav_estimator_init(mem, size, cfg, out);
    if (made != RELNAV_OK) {
        ::operator delete(mem, std::align_val_t(align));
        return made;
    }
    placed()[*out] = Placed{mem, align};
    return made;
#else
    return relnav_estimator_new(cfg, out);
#endif
}

inline void estimator_free(relnav_estimator* e) {
#ifdef RELNAV_FLIGHT
    if (e == nullptr) return;
    const auto it = placed().find(e);
    if (it == placed().end()) return;
    relnav_estimator_deinit(e);
    ::operator delete(it->second.storage, std::align_val_t(it->second.align));
    placed().erase(it);
#else
    relnav_estimator_free(e);
#endif
}

}  // namespace harness
