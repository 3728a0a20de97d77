#include "Hud.h"

#include <cstdio>
#include <string>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace marble {

Hud::Hud(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini dropped into the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

Hud::~Hud() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

bool Hud::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool Hud::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

void Hud::draw(const HudInfo& info) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  const Game& game = *info.game;
  const ViewState& view = *info.view;
  const tandem::FrameSettings& s = view.settings;
  const ImGuiWindowFlags overlay = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoNav;
  const ImVec2 display = ImGui::GetIO().DisplaySize;

  // Top right: the game itself — gems, clock, outcome.
  ImGui::SetNextWindowPos(ImVec2(display.x - 8.0f, 8.0f), ImGuiCond_Always, ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.55f);
  if (ImGui::Begin("game", nullptr, overlay)) {
    const bool flash = info.game->lastPickupTime() >= 0.0 && game.time() - game.lastPickupTime() < 0.6;
    ImGui::TextColored(flash ? ImVec4(1, 0.9f, 0.2f, 1) : ImVec4(1, 1, 1, 1), "Gems %d / %d", game.score(),
                       game.gemCount());
    ImGui::SameLine(0, 24);
    const double left = game.timeLeft();
    ImGui::TextColored(left < 10.0 ? ImVec4(1, 0.35f, 0.3f, 1) : ImVec4(1, 1, 1, 1), "Time %5.1f s", left);
    if (!view.showHelp) {
      ImGui::SameLine(0, 24);
      ImGui::TextDisabled("F1: keys");
    }
    if (info.paused) ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "PAUSED (TAB): the frame converges");
    if (game.outcome() == Outcome::Won)
      ImGui::TextColored(ImVec4(0.3f, 1, 0.4f, 1), "ALL GEMS! You win with %.1f s to spare. R to play again.", left);
    else if (game.outcome() == Outcome::Lost)
      ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "Time is up. R to try again.");
  }
  ImGui::End();

  if (view.showHud) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.55f);
    if (ImGui::Begin("stats", nullptr, overlay)) {
      const tandem::FrameStats& st = info.stats;
      ImGui::Text("%.1f fps  (%.1f ms/frame)", info.frameMs > 0 ? 1000.0 / info.frameMs : 0.0, info.frameMs);
      ImGui::Text("frame %dx%d  window %dx%d", s.width, s.height, info.framebufferW, info.framebufferH);
      ImGui::Separator();
      // Every stage of the frame (kFrameStages), with the GPU's own time of the GL ones beside it (timer
      // queries, from a frame or two ago). Stages that took nothing this frame are left out.
      ImGui::Text("stage          CPU ms   GPU ms");
      for (const tandem::FrameStage& stage : tandem::kFrameStages) {
        const double cpu = st.*stage.cpu;
        const double gpu = stage.gpu != nullptr && st.gpu.valid ? st.gpu.*stage.gpu : -1.0;
        if (cpu < 0.005 && gpu < 0.005) continue;
        if (gpu >= 0.0) ImGui::Text("%-12s %8.2f %8.2f", stage.name, cpu, gpu);
        else ImGui::Text("%-12s %8.2f", stage.name, cpu);
      }
      ImGui::Text("%-12s %8.2f", "untimed", st.untimedMs());
      // The renderer's whole frame; the GPU column is as old as the timer queries it was read from.
      if (st.gpu.valid) ImGui::Text("%-12s %8.2f %8.2f", "total", st.totalMs, st.gpu.totalMs());
      else ImGui::Text("%-12s %8.2f", "total", st.totalMs);
      if (st.gpu.valid) ImGui::TextDisabled("GPU times from %d frame(s) ago", st.gpu.framesAgo);
      ImGui::Text("rays: %dx%d on %d thr%s", st.rayWidth, st.rayHeight, st.threads,
                  st.raysReused ? "  reused: nothing moved" : "");
      ImGui::Text("window present %5.2f ms", info.presentMs);
      // Throughput mode: the frame shown is a frame old; its total above is its latency.
      if (st.pipelined)
        ImGui::Text("pipelined: 1 frame latency, rays waited %.2f ms%s", st.raysWaitMs,
                    st.pipelineDrained ? "  (drained: settings changed)" : "");
      // At rest the frame adds samples until it has FrameSettings::accumulate frames of them, then costs nothing.
      ImGui::Text("samples   %d this frame, %d per pixel shown", st.samples, st.accumulated);
      // A frame that compiled a shader stalled on it: worth seeing when it happens mid-game.
      if (st.shaderCompiles > 0) ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "shader compiles %d", st.shaderCompiles);
      ImGui::Text("probes/frame %d (0 = all)", s.probesPerFrame);
      ImGui::Separator();
      auto k = [](std::uint64_t n) { return static_cast<double>(n) / 1000.0; };
      ImGui::Text("rays/frame %.1fk: primary %.1fk", k(st.rays.total()), k(st.rays.primary));
      ImGui::Text("  shadow %.1fk  reflect %.1fk  refract %.1fk", k(st.rays.shadow), k(st.rays.reflection),
                  k(st.rays.refraction));
      // Shadow answers not traced: the hybrid shadows' tile shafts and maps, and those kept from the frame before.
      if (st.rays.shadowByShaft + st.rays.shadowByMap + st.rays.shadowKept > 0)
        ImGui::Text("  shadow answers: by shaft %.1fk  by map %.1fk  kept %.1fk", k(st.rays.shadowByShaft),
                    k(st.rays.shadowByMap), k(st.rays.shadowKept));
      ImGui::Separator();
      ImGui::Text("preset      %s", view.preset.c_str());
      ImGui::Text("shadows     %s  [1]", std::string(tandem::shadowModeName(s)).c_str());
      ImGui::Text("reflections %s  [2]", std::string(tandem::toString(s.reflections)).c_str());
      ImGui::Text("refraction  %s  [3]", std::string(tandem::toString(s.refraction)).c_str());
      ImGui::Text("shading     %s  [4]", view.shadingName().c_str());
      ImGui::Text("depth %d [5/6]  ray scale 1/%d [7]", s.maxDepth, s.rayScale);
      ImGui::Text("view %s [9]  render %d%% [0]", std::string(tandem::toString(s.debugView)).c_str(),
                  view.renderScalePct);
      ImGui::Text("vsync %s [V]  %s [F]", view.vsync ? "on" : "off", view.fullscreen ? "fullscreen" : "windowed");
      // The budget draws the settings above or a cheaper choice: show which, and what the model expected.
      ImGui::Text("budget %s [B]%s", view.budgetName().c_str(),
                  view.targetFps > 0.0f && !st.budget.active ? "  (not for the reference preset)" : "");
      if (st.budget.active) {
        ImGui::Text("  drawn: %s (step %d of %d)", tandem::describeBudget(st.budget).c_str(), st.budget.step,
                    st.budget.steps);
        ImGui::Text("  predicted %.1f ms  expected FLIP %+.4f", st.budget.predictedMs, st.budget.expectedError);
        if (!st.budget.reachable)
          ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "  out of reach: the cheapest choice is over %.1f ms",
                             st.budget.targetMs);
      }
      ImGui::Text("denoise %s [N]%s", s.denoise ? "on" : "off",
                  st.denoised ? (" filter " + std::to_string(static_cast<int>(st.denoiseMs + 0.5)) + " ms").c_str() : "");
      ImGui::Text("radiosity %s [G]", s.radiosity ? "on" : "off");
      if (s.radiosity) {
        if (!st.radiosity.active)
          ImGui::Text("  solving: the first solution is on its way");
        else
          ImGui::Text("  %d patches  %llu shots  unshot %.1f %%  %.0f ms%s", st.radiosity.patches,
                      static_cast<unsigned long long>(st.radiosity.shots), 100.0 * st.radiosity.residual,
                      st.radiosity.solveMs, st.radiosity.converged ? "  converged" : "");
      }
      const glm::vec3 p = game.marblePos();
      ImGui::Text("marble %.2f %.2f  speed %.2f", static_cast<double>(p.x), static_cast<double>(p.z),
                  static_cast<double>(glm::length(game.marbleVelXZ())));
      ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 300.0f);  // the context line is long; keep the HUD narrow
      ImGui::TextDisabled("%s", info.context);
      ImGui::PopTextWrapPos();
      if (info.message[0]) ImGui::TextColored(ImVec4(0.6f, 0.9f, 1, 1), "%s", info.message);
    }
    ImGui::End();
  }

  if (view.showHelp) {
    ImGui::SetNextWindowPos(ImVec2(display.x - 8.0f, display.y - 8.0f), ImGuiCond_Always, ImVec2(1.0f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.6f);
    if (ImGui::Begin("help", nullptr, overlay)) {
      ImGui::TextColored(ImVec4(1, 0.9f, 0.5f, 1), "Marble Mirrors: collect every gem before the clock runs out");
      for (const char* const* line = helpLines(); *line; ++line) ImGui::TextUnformatted(*line);
    }
    ImGui::End();
  }

  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace marble
