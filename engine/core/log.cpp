#include "speculum/core.hpp"

#include <atomic>
#include <cstdio>

namespace speculum {
namespace {
std::atomic<int> gWarnings{0};
LogLevel gLevel = LogLevel::Info;
}  // namespace

void setLogLevel(LogLevel level) { gLevel = level; }
int warningCount() { return gWarnings.load(); }

void log(LogLevel level, const std::string& message) {
    if (level == LogLevel::Warning) ++gWarnings;
    if (level < gLevel) return;
    static const char* const kPrefix[] = {"debug", "info", "warning", "error"};
    // Diagnostics go to stderr so that stdout stays parseable for tools that print results.
    std::fprintf(stderr, "[speculum] %s: %s\n", kPrefix[static_cast<int>(level)], message.c_str());
}

}  // namespace speculum
