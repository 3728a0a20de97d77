// The loaders' resource contract (docs/gltf.md and docs/scene-format.md, "Resources"), measured: every
// adversarial file of about 400 KB and 4 MB is loaded by tandem-load in a child process, whose peak
// memory (getrusage of the child) and time must stay within the documented bound for its input size.
// A load may succeed or be refused with a one-line message; it may not crash, hang or balloon.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/AdversarialFiles.h"
#include "support/TestSupport.h"
#include "tandem/Gltf.h"

extern char** environ;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TANDEM_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TANDEM_SANITIZED 1
#endif
#endif
#ifndef TANDEM_SANITIZED
#define TANDEM_SANITIZED 0
#endif

namespace tandem::test {
namespace {

namespace fs = std::filesystem;

struct ChildRun {
  int exitCode = -1;  // -1: killed by a signal
  int signal = 0;
  double seconds = 0.0;
  std::uint64_t peakBytes = 0;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs tandem-load on `file` in a child process with a wall-clock limit; its own rusage gives its peak RSS.
ChildRun load(const fs::path& file, const fs::path& scratch, int limitSeconds) {
  const std::string exe = std::string(TANDEM_BINARY_DIR) + "/bin/tandem-load";
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::string a0 = exe, a1 = file.string(), a2 = "--json";
  char* argv[] = {a0.data(), a1.data(), a2.data(), nullptr};
  ChildRun r;
  pid_t pid = 0;
  const auto start = std::chrono::steady_clock::now();
  if (posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv, environ) != 0) {
    posix_spawn_file_actions_destroy(&fa);
    ADD_FAILURE() << "cannot start " << exe;
    return r;
  }
  posix_spawn_file_actions_destroy(&fa);
  int status = 0;
  rusage ru{};
  for (;;) {
    const pid_t w = wait4(pid, &status, WNOHANG, &ru);
    if (w == pid) break;
    if (std::chrono::steady_clock::now() - start > std::chrono::seconds(limitSeconds)) {
      ::kill(pid, SIGKILL);
      wait4(pid, &status, 0, &ru);
      break;
    }
    ::usleep(2000);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFEXITED(status)) r.exitCode = WEXITSTATUS(status);
  else if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = slurp(out);
  r.err = slurp(err);
  // The child's own peak (VmHWM, printed by tandem-load): wait4's ru_maxrss would include this test
  // process's memory, which posix_spawn shared with the child until exec.
  const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  if (j.is_object() && j.contains("peakRssKiB")) r.peakBytes = j["peakRssKiB"].get<std::uint64_t>() * 1024;
  else r.peakBytes = std::uint64_t(ru.ru_maxrss) * 1024;  // no report (crashed): an upper bound
  return r;
}

// The contract (docs/gltf.md, "Resources"): a load holds at most the budget (base + perByte × input) for
// what it keeps and decodes, plus its JSON parse trees (kParseBytesPerByte × input), plus the process.
constexpr std::uint64_t kParseBytesPerByte = 48;
constexpr std::uint64_t kSlackBytes = 16u << 20;  // allocator and stack, beyond the process baseline

std::uint64_t bound(std::uint64_t inputBytes, std::uint64_t baseline) {
  const GltfLimits l;
  return baseline + kSlackBytes + l.budgetBaseBytes + (l.budgetBytesPerInputByte + kParseBytesPerByte) * inputBytes;
}

std::uint64_t baselineBytes() {
  static const std::uint64_t b = [] {
    // One folder per process: ctest runs each case as its own process, in parallel, and a shared
    // folder was removed under another case's child while it wrote its output there.
    const fs::path d = fs::path(outputDir()) / "resource" / ("baseline-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "a.gltf") << R"({"asset":{"version":"2.0"}})";
    const std::uint64_t peak = load(d / "a.gltf", d, 60).peakBytes;
    std::error_code ignored;
    fs::remove_all(d, ignored);
    return peak;
  }();
  return b;
}

class LoaderResource : public testing::TestWithParam<std::tuple<std::size_t, std::size_t>> {};

TEST_P(LoaderResource, PeakMemoryAndTimeWithinTheContract) {
  const auto [caseIndex, size] = GetParam();
  const AdversarialCase& c = adversarialCases()[caseIndex];
  const fs::path dir = fs::path(outputDir()) / "resource" / (c.name + "-" + std::to_string(size >> 10) + "k");
  fs::remove_all(dir);
  fs::create_directories(dir / "in");
  const fs::path file = c.write(dir / "in", size);
  const std::uint64_t input = folderBytes(dir / "in");
  // Time: O(input × log): 2 s beyond 1 µs per input byte (the 400 KB file of the report took 60 s and 17 GB).
  const double timeLimit = 2.0 + 1e-6 * double(input);
  const ChildRun r = load(file, dir, 60);
  const std::uint64_t limit = bound(input, baselineBytes());
  std::printf("[resource] %-26s input %8.2f MB  peak %8.1f MB (limit %7.1f)  %6.3f s  %s\n", c.name.c_str(),
              double(input) / 1e6, double(r.peakBytes) / 1e6, double(limit) / 1e6, r.seconds,
              r.exitCode == 0 ? "loaded" : r.exitCode == 1 ? ("refused: " + r.err.substr(0, 110)).c_str() : "CRASHED");
  EXPECT_EQ(r.signal, 0) << c.name << ": killed by signal " << r.signal << "\n" << r.err;
  EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 1) << c.name << ": exit " << r.exitCode << "\n" << r.err;
  if (r.exitCode == 1) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << ": a refusal is one line:\n" << r.err;
  }
#if TANDEM_SANITIZED
  // Sanitizer builds keep freed memory in quarantine and run several times slower: there the cases check
  // only that nothing crashes or trips the sanitizer; the bounds hold for the release build.
  (void)limit;
  (void)timeLimit;
#else
  EXPECT_LE(r.peakBytes, limit) << c.name << " (" << c.what << "): peak " << r.peakBytes << " bytes for " << input
                                << " input bytes";
  EXPECT_LE(r.seconds, timeLimit) << c.name << " (" << c.what << ")";
#endif
}

INSTANTIATE_TEST_SUITE_P(Adversarial, LoaderResource,
                         testing::Combine(testing::Range<std::size_t>(0, adversarialCases().size()),
                                          testing::Values(std::size_t(400) << 10, std::size_t(4) << 20)),
                         [](const testing::TestParamInfo<LoaderResource::ParamType>& p) {
                           std::string n = adversarialCases()[std::get<0>(p.param)].name + "_" +
                                           std::to_string(std::get<1>(p.param) >> 10) + "k";
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace tandem::test
