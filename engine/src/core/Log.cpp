#include "tandem/Log.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace tandem {
namespace {

std::mutex& logMutex() {
  static std::mutex m;
  return m;
}
LogSink& sinkRef() {
  static LogSink sink;
  return sink;
}
LogLevel& levelRef() {
  static LogLevel level = [] {
    const char* env = std::getenv("TANDEM_LOG");
    return env && std::strcmp(env, "debug") == 0 ? LogLevel::Debug : LogLevel::Info;
  }();
  return level;
}
const char* levelName(LogLevel l) {
  switch (l) {
    case LogLevel::Debug: return "debug";
    case LogLevel::Info: return "info";
    case LogLevel::Warning: return "warning";
    case LogLevel::Error: return "error";
  }
  return "?";
}

}  // namespace

LogSink setLogSink(LogSink sink) {
  std::lock_guard lock(logMutex());
  LogSink old = std::move(sinkRef());
  sinkRef() = std::move(sink);
  return old;
}

void setLogLevel(LogLevel level) {
  std::lock_guard lock(logMutex());
  levelRef() = level;
}

void log(LogLevel level, std::string_view message) {
  std::lock_guard lock(logMutex());
  if (level < levelRef()) return;
  if (sinkRef()) {
    sinkRef()(level, message);
    return;
  }
  std::fprintf(stderr, "tandem %s: %.*s\n", levelName(level), static_cast<int>(message.size()), message.data());
}

}  // namespace tandem
