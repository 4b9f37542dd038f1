// Errors that map to the command-line exit statuses of docs/design.md section 6 (command lines), and logging.
#pragma once
#include <stdexcept>
#include <string>

namespace speculum {

enum class ExitCode : int { Ok = 0, Failure = 1, BadArguments = 2, BadInput = 3, NoDevice = 4 };

// Every user-facing failure is an Error with the exit status the tools must return.
class Error : public std::runtime_error {
public:
    Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    ExitCode code() const { return code_; }

private:
    ExitCode code_;
};

// Bad command-line arguments or settings keys (exit 2).
inline Error argumentError(const std::string& message) { return {ExitCode::BadArguments, message}; }
// A bad scene or settings file; the message must name the file (exit 3).
inline Error inputError(const std::string& file, const std::string& problem) {
    return {ExitCode::BadInput, file + ": " + problem};
}
// No usable Vulkan device (exit 4).
inline Error deviceError(const std::string& message) { return {ExitCode::NoDevice, message}; }

enum class LogLevel { Debug, Info, Warning, Error };
void log(LogLevel level, const std::string& message);
inline void logInfo(const std::string& m) { log(LogLevel::Info, m); }
inline void logWarning(const std::string& m) { log(LogLevel::Warning, m); }
inline void logError(const std::string& m) { log(LogLevel::Error, m); }
void setLogLevel(LogLevel level);
// Count of warnings logged so far (tests use it to assert a warning was given).
int warningCount();

}  // namespace speculum
