#pragma once
// The engine's log. One sink for the whole process (stderr by default); tests install their own to
// capture messages. Thread-safe: the sink is called under a mutex.
#include <functional>
#include <string>
#include <string_view>

namespace tandem {

enum class LogLevel { Debug, Info, Warning, Error };

using LogSink = std::function<void(LogLevel, std::string_view)>;

/// Replaces the sink; returns the previous one. Pass nullptr to restore stderr.
LogSink setLogSink(LogSink sink);
/// Messages below this level are dropped (default Info; TANDEM_LOG=debug in the environment lowers it).
void setLogLevel(LogLevel level);
void log(LogLevel level, std::string_view message);
inline void logInfo(std::string_view m) { log(LogLevel::Info, m); }
inline void logWarning(std::string_view m) { log(LogLevel::Warning, m); }
inline void logError(std::string_view m) { log(LogLevel::Error, m); }

}  // namespace tandem
