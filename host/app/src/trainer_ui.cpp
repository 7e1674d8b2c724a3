#include "app/trainer_ui.hpp"

#include <cstdio>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "app/case_picker_panel.hpp"
#include "app/end_of_run_panel.hpp"
#include "app/gl.hpp"

namespace cathbox::app {
namespace {
constexpr std::size_t kMaxLines = 400;
constexpr double kRadToDeg = 57.29577951308232;
}  // namespace

TrainerUi::TrainerUi() : picker_(std::make_unique<CasePickerPanel>()) {}

TrainerUi::~TrainerUi() {
  picker_.reset();  // its textures, while the context is still there
  if (!ready_) return;
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

bool TrainerUi::init(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 3.0F;
  if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) return false;
  if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
    ImGui_ImplGlfw_Shutdown();
    return false;
  }
  ready_ = true;
  return true;
}

void TrainerUi::open_picker() { picker_->open(); }

void TrainerUi::begin_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void TrainerUi::end_frame() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void TrainerUi::add_line(std::string line) {
  lines_.push_back(std::move(line));
  while (lines_.size() > kMaxLines) lines_.pop_front();
  scroll_to_bottom_ = true;
}

void TrainerUi::drain(session::EventLog& log) {
  session::LogEvent e;
  char buf[160];
  while (log.pop(e)) {
    std::snprintf(buf, sizeof buf, "%8.3f s  %s", static_cast<double>(e.time_us) * 1e-6, e.text.data());
    add_line(buf);
  }
}

bool TrainerUi::wants_mouse() const { return ready_ && ImGui::GetIO().WantCaptureMouse; }
bool TrainerUi::wants_keyboard() const { return ready_ && ImGui::GetIO().WantCaptureKeyboard; }
float TrainerUi::mouse_wheel() const { return ready_ ? ImGui::GetIO().MouseWheel : 0.0F; }

namespace {

// A live run's controls in the HUD: the case, restart, end, switch tool, and the keys that apply.
void draw_run_controls(const UiStatus& status, const CaseCatalog& catalog, int current_case, UiActions& act) {
  if (!catalog.entries().empty()) {
    const std::string label = "cases (" + std::to_string(catalog.entries().size()) + ") ...";
    if (ImGui::Button(label.c_str())) act.open_picker = true;
    if (current_case >= 0) {
      ImGui::SameLine();
      ImGui::TextDisabled("%s", catalog.entries()[static_cast<std::size_t>(current_case)].name.c_str());
    }
  }
  if (ImGui::Button("restart")) act.restart = true;
  ImGui::SameLine();
  if (ImGui::Button("end run")) act.end_run = true;
  ImGui::SameLine();
  if (ImGui::Button("switch tool (Tab)")) act.switch_tool = true;
  ImGui::TextDisabled("Up/Down push/pull, Left/Right twist, Shift fast");
  if (status.can_detach) ImGui::TextDisabled("K: detach the coil");
  if (status.detaching) ImGui::TextDisabled("detaching the coil: hold the pusher still");
  if (status.can_load) ImGui::TextDisabled("L: load the next coil");
  if (status.aspiration >= 0) ImGui::TextDisabled("V: aspiration %s", status.aspiration == 1 ? "ON (V: off)" : "off");
  if (status.balloon_guide >= 0) ImGui::TextDisabled("B: balloon guide %s", status.balloon_guide == 1 ? "INFLATED (flow arrest)" : "deflated");
  for (const std::string& line : status.drive_hints) ImGui::TextDisabled("%s", line.c_str());
}

}  // namespace

UiActions TrainerUi::draw(const ScreenLayout& layout, const session::SceneSnapshot& s, const UiStatus& status,
                          const CaseCatalog& catalog, int current_case, RenderSettings& settings) {
  UiActions act;
  constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                      ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;

  // HUD, top left of the global view.
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(layout.global.x) + 8.0F, static_cast<float>(layout.global.y) + 8.0F));
  ImGui::SetNextWindowBgAlpha(0.75F);
  if (ImGui::Begin("Cathbox", nullptr, kFixed | ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("case      %s", status.case_name.c_str());
    ImGui::Text("tool      %s", status.tool_name.c_str());
    ImGui::Separator();
    ImGui::Text("insertion %8.1f mm", s.insertion_mm);
    ImGui::Text("rotation  %8.1f deg", s.rotation_rad * kRadToDeg);
    ImGui::Text("hand      %8.1f mN  %7.2f mNm", s.hand_force_mN, s.hand_torque_mNmm * 1e-3);
    ImGui::Text("contacts  %8zu", s.contacts.size());
    ImGui::Separator();
    ImGui::Text("haptic    %8.0f Hz (%lld dropped)", s.haptic_rate_hz, static_cast<long long>(s.dropped_ticks));
    ImGui::Text("display   %8.1f fps", status.fps);
    ImGui::Text("%s %s", status.replay ? "replay   " : "hand     ", status.device.c_str());
    ImGui::Text("time      %8.1f s", static_cast<double>(s.sim_time_us) * 1e-6);
    ImGui::Separator();
    ImGui::Checkbox("wireframe", &settings.wireframe);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(110.0F);
    ImGui::SliderFloat("opacity", &settings.vessel_alpha, 0.05F, 1.0F, "%.2f");
    if (!status.replay) draw_run_controls(status, catalog, current_case, act);
    ImGui::TextDisabled("drag: orbit, right-drag: pan, wheel: zoom");
    ImGui::TextDisabled("double-click a vessel: orbit around it; C: reset");
    const ImVec2 p = ImGui::GetWindowPos();
    const ImVec2 sz = ImGui::GetWindowSize();
    hud_rect_ = {static_cast<int>(p.x), static_cast<int>(p.y), static_cast<int>(sz.x), static_cast<int>(sz.y)};
  }
  ImGui::End();

  // Output panel, lower right.
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(layout.output.x), static_cast<float>(layout.output.y)));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(layout.output.width), static_cast<float>(layout.output.height)));
  if (ImGui::Begin("Output", nullptr, kFixed)) {
    for (const std::string& line : lines_) ImGui::TextUnformatted(line.c_str());
    if (scroll_to_bottom_) ImGui::SetScrollHereY(1.0F);
    scroll_to_bottom_ = false;
  }
  ImGui::End();

  // The case picker over the global view, when asked for (the HUD's button, --picker).
  if (act.open_picker) picker_->open();
  if (!status.replay) {
    const int picked = picker_->draw(layout.global, catalog, current_case);
    if (picked >= 0) act.pick_case = picked;
  }

  // End of run, centred on the global view.
  if (s.run_over) {
    const EndOfRunActions end = draw_end_of_run(layout.global, s.metrics, status.record, status.replay);
    act.restart = act.restart || end.again;
    act.replay_this_run = end.replay;
  }
  return act;
}

}  // namespace cathbox::app
