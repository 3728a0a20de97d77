// Runs the built tandem-game the way a user does: headless with a script (state and golden frame),
// every toggle key (each must change the frame), bad input, and a real window under Xvfb.
//
// Goldens: tests/golden/game/*.png. Regenerate after an intended rendering change with
//   TANDEM_UPDATE_GOLDENS=1 ctest --test-dir build -L game
// then look at the new images before committing them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "support/Goldens.h"

#include <gtest/gtest.h>

#include "tandem/FrameStats.h"
#include "tandem/Image.h"

namespace {

namespace fs = std::filesystem;

std::string outDir() {
  fs::path p = fs::path(TANDEM_BINARY_DIR) / "test-output" / "game";
  fs::create_directories(p);
  return p.string();
}
std::string src(const std::string& rel) { return (fs::path(TANDEM_SOURCE_DIR) / rel).string(); }

struct Outcome {
  int exitCode = -1;
  std::string output;
};

Outcome runCommand(const std::string& cmd) {
  Outcome r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), p)) r.output += buf.data();
  const int status = pclose(p);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Outcome runGame(const std::string& args) { return runCommand(std::string("'") + TANDEM_GAME_EXE + "' " + args); }

/// key=value pairs of the lines that start with `prefix` ("game: ", "reuse: ").
std::map<std::string, std::string> keyValues(const std::string& output, const std::string& prefix) {
  std::map<std::string, std::string> kv;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) != 0) continue;
    std::istringstream words(line.substr(prefix.size()));
    for (std::string w; words >> w;)
      if (auto eq = w.find('='); eq != std::string::npos) kv[w.substr(0, eq)] = w.substr(eq + 1);
  }
  return kv;
}
std::map<std::string, std::string> gameState(const std::string& output) { return keyValues(output, "game: "); }
/// The `reuse:` line of --check-reuse.
std::map<std::string, std::string> reuseLine(const std::string& output) { return keyValues(output, "reuse: "); }

struct Diff {
  double meanAbs = 0.0;        // mean |a - b| over all channels, in 1/255 units
  double fractionWithin = 0.0; // pixels whose every channel is within the tolerance
};
Diff compare(const tandem::Image& a, const tandem::Image& b, int tolerance) {
  Diff d;
  const std::size_t pixels = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
  std::size_t within = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    bool ok = true;
    for (std::size_t c = 0; c < 3; ++c) {
      const int e = std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c]));
      sum += e;
      ok = ok && e <= tolerance;
    }
    within += ok ? 1 : 0;
  }
  d.meanAbs = sum / static_cast<double>(pixels * 3);
  d.fractionWithin = static_cast<double>(within) / static_cast<double>(pixels);
  return d;
}

tandem::Image load(const std::string& path) {
  auto r = tandem::readPng(path);
  EXPECT_TRUE(r.ok()) << path << ": " << (r ? "" : r.error().message);
  return r ? *r : tandem::Image{};
}

/// Compares a capture with its golden, or rewrites the golden under --update-goldens (the update-goldens target).
void expectMatchesGolden(const std::string& capture, const std::string& goldenName, int tolerance,
                         double minFraction, double maxMeanAbs) {
  const std::string golden = src("tests/golden/game/" + goldenName);
  ASSERT_EQ(tandem::test::strayGoldenUpdate(), "");
  if (tandem::test::updatingGoldens()) {
    fs::copy_file(capture, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "updated " << golden << " (look at it before committing)";
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; create it: cmake --build build --target update-goldens";
  const tandem::Image a = load(capture), b = load(golden);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  const Diff d = compare(a, b, tolerance);
  EXPECT_GE(d.fractionWithin, minFraction) << capture << " vs " << golden << ": mean abs " << d.meanAbs;
  EXPECT_LE(d.meanAbs, maxMeanAbs) << capture << " vs " << golden;
}

/// A deterministic run of the game shared by several tests: ctest runs each test in a process of its own, so
/// the first to need it runs the game and keeps its outcome in test-output/game/<name>.outcome, and the others
/// read it, as long as it is newer than the game and the script and was made with the same arguments. A lock
/// makes tests run in parallel (ctest -j) wait for the one that runs it.
Outcome sharedGameRun(const std::string& name, const std::string& args, const std::string& script) {
  const fs::path dir = outDir(), cache = dir / (name + ".outcome");
  const int lock = ::open((dir / (name + ".lock")).c_str(), O_CREAT | O_RDWR, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  Outcome r;
  std::error_code ec;
  bool fresh = fs::exists(cache, ec) && fs::last_write_time(cache, ec) > fs::last_write_time(TANDEM_GAME_EXE, ec) &&
               fs::last_write_time(cache, ec) > fs::last_write_time(script, ec);
  if (fresh) {
    std::ifstream in(cache);
    std::string storedArgs, code;
    fresh = std::getline(in, storedArgs) && storedArgs == args && std::getline(in, code);
    if (fresh) {
      r.exitCode = std::atoi(code.c_str());
      std::ostringstream rest;
      rest << in.rdbuf();
      r.output = rest.str();
    }
  }
  if (!fresh) {
    r = runGame(args);
    std::ofstream out(cache, std::ios::trunc);
    out << args << "\n" << r.exitCode << "\n" << r.output;
  }
  if (lock >= 0) {
    ::flock(lock, LOCK_UN);
    ::close(lock);
  }
  return r;
}

// The scripted run is shared by the state and golden tests (it renders 330 frames), across their processes.
class ScriptedRun : public ::testing::Test {
 protected:
  static const Outcome& raster() {
    static const Outcome r =
        sharedGameRun("collect3-raster",
                      "--headless --frames 330 --size 320x180 --preset raster --script '" +
                          src("tests/game/collect3.script") + "' --capture '" + outDir() + "/collect3-raster.png'",
                      src("tests/game/collect3.script"));
    return r;
  }
  static const Outcome& hybrid() {
    static const Outcome r =
        sharedGameRun("collect3-hybrid-fast",
                      "--headless --frames 330 --size 320x180 --preset hybrid-fast --script '" +
                          src("tests/game/collect3.script") + "' --capture '" + outDir() + "/collect3-hybrid-fast.png'",
                      src("tests/game/collect3.script"));
    return r;
  }
};

void expectCollect3State(const Outcome& r) {
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto s = gameState(r.output);
  ASSERT_FALSE(s.empty()) << "no 'game: ' line in:\n" << r.output;
  EXPECT_EQ(s["state"], "playing");
  EXPECT_EQ(s["score"], "3/8");
  EXPECT_EQ(s["frames"], "330");
  EXPECT_EQ(s["time"], "5.500");
  float x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(s["pos"].c_str(), "%f,%f,%f", &x, &y, &z), 3) << s["pos"];
  // Where the marble stops after the script (GL-free physics, so this holds on any machine).
  EXPECT_NEAR(x, 7.895f, 0.05f);
  EXPECT_NEAR(y, 0.400f, 1e-3f);
  EXPECT_NEAR(z, -1.735f, 0.05f);
}

TEST_F(ScriptedRun, HeadlessScriptReachesKnownState) { expectCollect3State(raster()); }

TEST_F(ScriptedRun, SceneHasNoFacesFightingForDepth) {
  // The game checks its scene with tandem::coplanarOverlaps and logs what it finds; its glass pillars used to
  // stand exactly on the floor, so their bases flickered (41 % of neighbouring pixels jumped).
  ASSERT_EQ(raster().exitCode, 0) << raster().output;
  EXPECT_EQ(raster().output.find("depth fighting"), std::string::npos) << raster().output;
}

TEST_F(ScriptedRun, RasterCaptureMatchesGolden) {
  ASSERT_EQ(raster().exitCode, 0) << raster().output;
  // Raster preset: no ray pass, so the frame is GL only; allow 2/255 per channel on 99.9 % of pixels.
  expectMatchesGolden(outDir() + "/collect3-raster.png", "collect3-raster.png", 2, 0.999, 1.0);
}

TEST_F(ScriptedRun, HybridCaptureMatchesGolden) {
  expectCollect3State(hybrid());
  // Ray preset: the CPU ray pass at half resolution and its upsampling may round differently across
  // builds; require 99 % of pixels within 8/255 and a mean absolute difference under 1/255.
  expectMatchesGolden(outDir() + "/collect3-hybrid-fast.png", "collect3-hybrid-fast.png", 8, 0.99, 1.0);
}

TEST(GameRun, EveryToggleKeyChangesTheFrame) {
  // Each key (pressed `times` at t = 0) must change the picture. The measure is the fraction of pixels
  // that changed by more than 2/255. Shading keys are measured with reflections and refraction off: the
  // only curved surface is the glass marble (about 1.5 % of this frame), whose colour is otherwise mostly
  // reflected and refracted light, which the shading model does not touch. 0.2 % is the bar.
  const std::string effects = "--preset hybrid-fast";
  const std::string shadingOnly = "--preset hybrid-fast --reflections off --refraction off";
  struct Key {
    const char* key;
    int times;
    const char* what;
    const std::string* flags;
  } keys[] = {
      {"1", 1, "shadows ray->hybrid (the same frame: must not change)", &effects},
      {"1", 2, "shadows ray->hybrid->off", &effects},  {"2", 1, "reflections ray->off", &effects},
      {"3", 1, "refraction raster->ray", &effects},    {"4", 1, "shading -> flat", &shadingOnly},
      {"4", 2, "shading -> gouraud", &shadingOnly},    {"4", 4, "shading -> toon", &shadingOnly},
      {"5", 1, "depth 2->1", &effects},                {"7", 1, "ray scale 1/2->1/4", &effects},
      {"8", 1, "preset -> hybrid-full", &effects},     {"9", 1, "debug view -> depth", &effects},
      {"R", 1, "restart (same frame at t=0: must not change)", &effects},
  };
  std::map<const std::string*, tandem::Image> bases;
  for (const std::string* flags : {&effects, &shadingOnly}) {
    const std::string base = outDir() + "/toggle-base" + (flags == &effects ? "" : "-shading") + ".png";
    Outcome r = runGame("--headless --frames 1 --size 320x180 " + *flags + " --capture '" + base + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    bases[flags] = load(base);
  }
  for (const Key& k : keys) {
    const std::string tag = std::string(k.key) + "x" + std::to_string(k.times);
    const std::string script = outDir() + "/press-" + tag + ".script";
    FILE* f = std::fopen(script.c_str(), "w");
    ASSERT_NE(f, nullptr);
    for (int i = 0; i < k.times; ++i) std::fprintf(f, "0 press %s\n", k.key);
    std::fclose(f);
    const std::string out = outDir() + "/toggle-" + tag + ".png";
    Outcome r = runGame("--headless --frames 1 --size 320x180 " + *k.flags + " --script '" + script +
                        "' --capture '" + out + "'");
    ASSERT_EQ(r.exitCode, 0) << tag << ": " << r.output;
    const double changed = 1.0 - compare(load(out), bases[k.flags], 2).fractionWithin;
    if (std::string(k.key) == "R" || (std::string(k.key) == "1" && k.times == 1))
      EXPECT_LT(changed, 0.001) << k.what << ": the frame changed: " << out;
    else
      EXPECT_GT(changed, 0.002) << "key " << k.key << " x" << k.times << " (" << k.what
                                << ") did not change the frame: " << out;
  }
}

TEST(GameRun, ToggleKeysReachTheSettings) {
  Outcome r = runGame("--headless --frames 2 --size 64x36 --preset hybrid-fast --script '" +
                  src("tests/game/toggles.script") + "'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto s = gameState(r.output);
  EXPECT_EQ(s["preset"], "custom");
  EXPECT_EQ(s["shadows"], "off");
  EXPECT_EQ(s["reflections"], "off");
  EXPECT_EQ(s["refraction"], "ray");
  EXPECT_EQ(s["shading"], "flat");
  EXPECT_EQ(s["scale"], "4");
  EXPECT_EQ(s["depth"], "3");
  EXPECT_EQ(s["budget"], "60");
  EXPECT_EQ(s["radiosity"], "on");
  EXPECT_EQ(s["denoise"], "on");
}

TEST(GameRun, RadiositySolvesInTheBackgroundWhileTheGamePlays) {
  // The hall's radiosity runs on a thread of its own: the scripted run's frames go on while it solves, and
  // the marble rolling (a dynamic instance, out of the solution) does not restart it, so a solution is shown
  // (how far it gets depends on the machine's speed: only that it shows one and shot something is checked).
  Outcome r = runGame("--headless --frames 330 --size 160x90 --radiosity on --script '" +
                      src("tests/game/collect3.script") + "'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto s = gameState(r.output);
  EXPECT_EQ(s["radiosity"], "on");
  EXPECT_EQ(s["frames"], "330");
  ASSERT_FALSE(s["radiosity-shots"].empty()) << "no solution shown in:\n" << r.output;
  EXPECT_GT(std::stoull(s["radiosity-shots"]), 0u) << r.output;
  EXPECT_LT(std::stod(s["radiosity-unshot"]), 1.0) << r.output;
}

// One line of the game's --frame-log (a CSV whose one text field is quoted).
std::vector<std::string> csvCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    else if (ch == ',' && !quoted) cells.push_back(cell), cell.clear();
    else cell += ch;
  }
  cells.push_back(cell);
  return cells;
}

TEST(GameRun, BudgetLogsEachFrameAndItsErrorAgainstTheRequest) {
  // 1000 fps is out of reach: the budget gives things up, and the log says what each frame was drawn with.
  // Every 3rd frame is also drawn as requested by a second renderer: FLIP 0 where the budget drew the
  // request itself (the second renderer follows the game exactly), > 0 where it gave something up.
  const std::string log = outDir() + "/budget-log.csv";
  Outcome r = runGame("--headless --frames 12 --size 160x90 --preset hybrid-full --target-fps 1000 --frame-log '" +
                      log + "' --error-every 3 --script '" + src("tests/game/collect3.script") + "'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(gameState(r.output)["budget"], "1000");
  EXPECT_NE(r.output.find("budget: target_ms=1.00 frames=12"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reachable=0"), std::string::npos) << r.output;
  std::ifstream f(log);
  std::string line;
  ASSERT_TRUE(std::getline(f, line));
  EXPECT_EQ(line.rfind("frame,total_ms,", 0), 0u) << line;
  const std::vector<std::string> header = csvCells(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << "--frame-log has no column " << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t frameCol = column("frame"), flipCol = column("flip"), stepCol = column("step"),
                    totalCol = column("total_ms"), untimedCol = column("untimed_ms");
  int rows = 0, exact = 0, cut = 0;
  while (std::getline(f, line)) {
    const std::vector<std::string> cells = csvCells(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    EXPECT_EQ(std::stoi(cells[frameCol]), rows);
    // Every stage's time is there, and together they make the frame's total within 2 %.
    double stages = 0.0;
    for (const tandem::FrameStage& stage : tandem::kFrameStages) stages += std::stod(cells[column(std::string(stage.name) + "_ms")]);
    const double total = std::stod(cells[totalCol]);
    EXPECT_NEAR(stages + std::stod(cells[untimedCol]), total, 1e-3 * total + 1e-3) << line;
    EXPECT_LE(std::abs(total - stages), 0.02 * total) << line;
    EXPECT_EQ(cells[flipCol].empty(), rows % 3 != 0) << line;
    if (!cells[flipCol].empty()) {
      const double flip = std::stod(cells[flipCol]);
      if (cells[stepCol] == "0") {
        EXPECT_EQ(flip, 0.0) << "drawn as requested, yet different: " << line;
        ++exact;
      } else {
        EXPECT_GT(flip, 0.0) << "drawn with less, yet identical: " << line;
        ++cut;
      }
    }
    ++rows;
  }
  EXPECT_EQ(rows, 12);
  EXPECT_GE(exact, 1);  // frame 0: nothing measured yet, the request itself
  EXPECT_GE(cut, 1);
}

/// Plays `frames` frames headless with --check-reuse and returns its `reuse:` line, having checked that every
/// frame equals the one a second renderer traced whole, to the bit (linear and display values).
std::map<std::string, std::string> playCheckingReuse(const std::string& args, int frames) {
  Outcome r = runGame("--headless --check-reuse --frames " + std::to_string(frames) + " " + args);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  auto kv = reuseLine(r.output);
  EXPECT_EQ(kv["frames"], std::to_string(frames)) << r.output;
  EXPECT_EQ(kv["identical"], std::to_string(frames)) << r.output;
  EXPECT_EQ(kv["differing_pixels"], "0");
  EXPECT_EQ(kv["budget_frames_unchecked"], "0");
  if (kv.count("rays") == 0) kv["rays"] = kv["rays_without_reuse"] = kv["saved"] = kv["shadow_saved"] = kv["shadow_kept"] = "0";
  return kv;
}

// Reuse across frames is exact: every frame of the scripted run drawn with reuse (on by default) equals
// the same frame traced whole. The follow camera moves in almost every frame of this run, so little is
// kept (docs/reuse.md).
TEST(GameRun, ReuseIsExactOverTheScriptedRun) {
  auto kv = playCheckingReuse("--size 320x180 --script '" + src("tests/game/collect3.script") + "'", 330);
  EXPECT_LE(std::stoull(kv["rays"]), std::stoull(kv["rays_without_reuse"]));
}

// A player who stops to look: the camera stands, the key light and most of the arena stand, the orbiting
// lights and the spinners move. The shadow answers clear of what moved are kept, exactly: measured 22 %
// of the shadow rays saved at this size (hybrid-fast); with hybrid shadows, the maps and the kept answers
// together are still the traced frame.
TEST(GameRun, ReuseKeepsTheShadowsOfWhatStandsStillWhileThePlayerWatches) {
  const std::string idle = " --script '" + src("tests/game/idle.script") + "'";
  auto kv = playCheckingReuse("--size 320x180" + idle, 120);
  EXPECT_GT(std::stod(kv["shadow_saved"]), 0.15);
  EXPECT_GT(std::stod(kv["saved"]), 0.08);
  auto hybrid = playCheckingReuse("--size 160x90 --preset hybrid-full --shadows hybrid" + idle, 40);
  EXPECT_GT(std::stoull(hybrid["shadow_kept"]), 0u);
}

// Accumulation in the game (docs/antialiasing.md): in play the spinners, gems and lights move every frame, so
// each frame is one jittered sample; paused (TAB), nothing in view changes and the frame converges to the
// game's 16 samples, and then draws nothing more.
TEST(GameRun, PausedTheFrameConvergesToItsAccumulatedSamples) {
  Outcome idle = runGame("--headless --frames 60 --size 160x90 --script '" + src("tests/game/idle.script") + "'");
  ASSERT_EQ(idle.exitCode, 0) << idle.output;
  EXPECT_EQ(gameState(idle.output)["accumulated"], "1") << idle.output;
  Outcome paused = runGame("--headless --frames 60 --size 160x90 --script '" + src("tests/game/pause.script") + "'");
  ASSERT_EQ(paused.exitCode, 0) << paused.output;
  auto s = gameState(paused.output);
  EXPECT_EQ(s["accumulated"], "16") << paused.output;
  EXPECT_EQ(s["time"], "0.500") << "the game's clock stops while paused";
  EXPECT_EQ(s["accumulate"], "16");
  // Without accumulation the paused frame stays one sample deep.
  Outcome plain = runGame("--headless --frames 60 --size 160x90 --accumulate 0 --script '" +
                          src("tests/game/pause.script") + "'");
  ASSERT_EQ(plain.exitCode, 0) << plain.output;
  EXPECT_EQ(gameState(plain.output)["accumulated"], "1") << plain.output;
}

TEST(GameRun, CheckReuseRefusesWhatItCannotCompare) {
  for (const char* args : {"--frames 2 --check-reuse", "--headless --frames 2 --check-reuse --target-fps 30",
                           "--headless --frames 2 --check-reuse --reuse off"}) {
    Outcome r = runGame(args);
    EXPECT_NE(r.exitCode, 0) << args;
    EXPECT_NE(r.output.find("--check-reuse:"), std::string::npos) << args << "\n" << r.output;
  }
}

TEST(GameRun, BadInputFailsWithAMessage) {
  Outcome r = runGame("--headless --frames 1 --preset nope");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("unknown preset 'nope'"), std::string::npos) << r.output;

  const std::string script = outDir() + "/bad.script";
  FILE* f = std::fopen(script.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("0.5 down W\n1.0 jump W\n", f);
  std::fclose(f);
  r = runGame("--headless --frames 1 --script '" + script + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("line 2: unknown action 'jump'"), std::string::npos) << r.output;

  r = runGame("--headless");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;

  r = runGame("--headless --frames 1 --error-every 2");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("--error-every: needs --frame-log"), std::string::npos) << r.output;
  r = runGame("--headless --frames 1 --target-fps 0");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("--target-fps"), std::string::npos) << r.output;
}

TEST(GameRun, WindowUnderXvfbCapturesFrameAndHud) {
  if (runCommand("command -v xvfb-run").exitCode != 0) GTEST_SKIP() << "xvfb-run not installed (Debian 'xvfb')";
  const std::string dir = outDir() + "/xvfb";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Outcome r = runCommand(std::string("xvfb-run -a -s '-screen 0 1280x720x24' '") + TANDEM_GAME_EXE +
                           "' --frames 20 --size 640x360 --preset raster --script '" + src("tests/game/window.script") +
                           "' --shots '" + dir + "' --capture '" + dir + "/last.png'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto s = gameState(r.output);
  EXPECT_EQ(s["frames"], "20") << r.output;

  // --capture writes the frame and the window (with the HUD); the scripted P key wrote marble-000.
  for (const char* name : {"last.png", "last-window.png", "marble-000.png", "marble-000-window.png"})
    ASSERT_TRUE(fs::exists(dir + "/" + name)) << name << "\n" << r.output;
  const tandem::Image frame = load(dir + "/last.png");
  const tandem::Image window = load(dir + "/last-window.png");
  EXPECT_EQ(window.width, 640);
  EXPECT_EQ(window.height, 360);
  ASSERT_EQ(frame.width, window.width);
  ASSERT_EQ(frame.height, window.height);
  // The window is the frame with the HUD over it: its panel on the left (x 8..~320, the whole height) and its
  // status strip along the top. Away from both (right of x = 340, below y = 48) every pixel is the frame's;
  // inside the panel almost none is (measured 2026-11-27: 100 % and 99.98 %).
  auto fractionWithin = [&](int x0, int y0, int x1, int y1) {
    int within = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(frame.width) + static_cast<std::size_t>(x));
        int worst = 0;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(frame.rgba[i + c]) - int(window.rgba[i + c])));
        within += worst <= 2 ? 1 : 0;
      }
    return static_cast<double>(within) / static_cast<double>((x1 - x0) * (y1 - y0));
  };
  EXPECT_GE(fractionWithin(340, 48, 640, 360), 0.999) << "the window does not show the rendered frame there";
  EXPECT_LE(fractionWithin(8, 8, 300, 350), 0.1) << "no HUD panel drawn over the frame";
}

}  // namespace
