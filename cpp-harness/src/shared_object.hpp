// One dlopen()ed FMU binary for the masters (fmu_master, fmu3_master): opened with
// RTLD_NODELETE, so that the library stays mapped after dlclose and with it the statics it
// fills once (the description it generates): LeakSanitizer would otherwise report them as
// lost when the library is unmapped. Symbols are looked up by name.
#pragma once

#include <dlfcn.h>

#include <stdexcept>
#include <string>

namespace harness {

class SharedObject {
public:
    explicit SharedObject(const std::string& path) {
        handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        if (!handle_) throw std::runtime_error(std::string("dlopen failed: ") + dlerror());
    }
    ~SharedObject() {
        if (handle_) dlclose(handle_);
    }
    SharedObject(const SharedObject&) = delete;
    SharedObject& operator=(const SharedObject&) = delete;

    // The exported symbol `name`, or null.
    void* symbol(const char* name) const { return dlsym(handle_, name); }

private:
    void* handle_ = nullptr;
};

}  // namespace harness
