// Minimal test helpers: CHECK(...) records a failure (with file:line) and carries on, so one
// run reports every problem; the test's exit status is the failure count (capped).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace harness {

inline int& failure_count() {
    static int n = 0;
    return n;
}

inline void record_failure(const char* file, int line, const std::string& what) {
    ++failure_count();
    std::printf("FAIL %s:%d: %s\n", file, line, what.c_str());
    std::fflush(stdout);
}

inline int finish(const char* test_name) {
    const int n = failure_count();
    if (n == 0) {
        std::printf("%s: all checks passed\n", test_name);
        return EXIT_SUCCESS;
    }
    std::printf("%s: %d check(s) FAILED\n", test_name, n);
    return EXIT_FAILURE;
}

// Parse "--runs N" (and nothing else); returns def when absent.
inline int parse_runs(int argc, char** argv, int def) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--runs") == 0) return std::atoi(argv[i + 1]);
    return def;
}

}  // namespace harness

#define CHECK(cond)                                                              \
    do {                                                                         \
        if (!(cond)) ::harness::record_failure(__FILE__, __LINE__, "CHECK(" #cond ")"); \
    } while (0)

#define CHECK_MSG(cond, msg)                                                     \
    do {                                                                         \
        if (!(cond)) ::harness::record_failure(__FILE__, __LINE__, std::string("CHECK(" #cond "): ") + (msg)); \
    } while (0)
