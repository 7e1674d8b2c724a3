// cathbox-trainee.js: the session for the trainee page (host/server/web/train.html), loaded in
// its dedicated Web Worker (js/train_worker.js), which owns the clock. C functions for the
// worker's cwrap; one session at a time. Errors: a null/false result and cbx_error()'s line.
#include <emscripten/emscripten.h>

#include <cstring>
#include <iterator>
#include <memory>
#include <string>

#include "app/fluoro_shaders.hpp"
#include "protocol/cbx_command_report.h"
#include "session/replay.hpp"
#include "wasm/browser_session.hpp"
#include "wasm/surface_file.hpp"

namespace {

std::unique_ptr<cathbox::wasm::BrowserSession> g_session;
std::string g_error;
std::string g_text;
std::uint8_t g_command[CBX_REPORT_SIZE];

const cathbox::wasm::BrowserFluoro* fluoro() { return g_session ? &g_session->fluoro() : nullptr; }

}  // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE int cbx_open(const char* case_path, const char* mesh_path, const char* record_path) {
  g_session.reset();
  g_error.clear();
  auto opened = cathbox::wasm::BrowserSession::open(case_path, mesh_path, record_path);
  if (!opened) {
    g_error = opened.error().message;
    return 0;
  }
  g_session = std::move(opened.value());
  return 1;
}

EMSCRIPTEN_KEEPALIVE const char* cbx_error() { return g_error.c_str(); }

// U / E pressed (1 each): the stent's drive (BrowserSession::drive_keys), taken at the next tick.
EMSCRIPTEN_KEEPALIVE void cbx_drive_keys(int unsheathe, int retrieve) {
  if (g_session) g_session->drive_keys(unsheathe != 0, retrieve != 0);
}

// The drive's HUD lines and notes as JSON (BrowserSession::drive_json).
EMSCRIPTEN_KEEPALIVE const char* cbx_drive() {
  g_text = g_session ? g_session->drive_json() : std::string("{\"hints\":[],\"notes\":[]}");
  return g_text.c_str();
}

EMSCRIPTEN_KEEPALIVE void cbx_next_tool() {
  if (g_session) g_session->next_tool();
}

EMSCRIPTEN_KEEPALIVE void cbx_end_run() {
  if (g_session) g_session->end_run();
}

// The haptic worker's real clock has dropped `total` ticks so far (its record and metrics keep it).
EMSCRIPTEN_KEEPALIVE void cbx_note_dropped(double total) {
  if (g_session) g_session->note_dropped(static_cast<std::int64_t>(total));
}

// One tick with the keys held (mm/s, rad/s; steering 1: a movement key held; box 1: a box drives
// the tools): BrowserSession::tick. 1 while the run goes on.
EMSCRIPTEN_KEEPALIVE int cbx_tick(double insert_mm_s, double rotate_rad_s, int steering, int box) {
  return g_session && g_session->tick(insert_mm_s, rotate_rad_s, steering != 0, box != 0) ? 1 : 0;
}

EMSCRIPTEN_KEEPALIVE int cbx_over() { return g_session && g_session->over() ? 1 : 0; }

EMSCRIPTEN_KEEPALIVE double cbx_ticks() { return g_session ? static_cast<double>(g_session->ticks()) : 0.0; }

// The snapshot's floats: cbx_snapshot() packs it and returns its length, cbx_snapshot_data() where.
EMSCRIPTEN_KEEPALIVE int cbx_snapshot() { return g_session ? static_cast<int>(g_session->pack_snapshot()) : 0; }
EMSCRIPTEN_KEEPALIVE const float* cbx_snapshot_data() { return g_session ? g_session->packed() : nullptr; }

// The packed snapshot's metrics as JSON ({name: value}), after cbx_snapshot().
EMSCRIPTEN_KEEPALIVE const char* cbx_snapshot_metrics() {
  g_text = g_session ? g_session->snapshot_metrics_json() : std::string("{}");
  return g_text.c_str();
}

EMSCRIPTEN_KEEPALIVE int cbx_close_record() {
  g_error.clear();
  if (!g_session) return 0;
  const cathbox::base::Status<> closed = g_session->close_record();
  if (!closed) g_error = closed.error().message;
  return closed ? 1 : 0;
}

EMSCRIPTEN_KEEPALIVE const char* cbx_summary() {
  g_text = g_session ? g_session->summary_json() : std::string("null");
  return g_text.c_str();
}

// The fluoroscopy (wasm/browser_fluoro.hpp). cbx_fluoro_open(): 1 when the case has a
// fluoroscopy unit, its lumen (vertices, 6 floats each; triangle indices) then at the pointers
// below. cbx_fluoro_frame(w, h) after cbx_snapshot(): the header (FluoroHeader, doubles); the
// phantom (2 floats a pixel) and the scenes (floats, indices) are new when their versions are.
EMSCRIPTEN_KEEPALIVE int cbx_fluoro_open() { return g_session && g_session->open_fluoro() ? 1 : 0; }
EMSCRIPTEN_KEEPALIVE void cbx_fluoro_keys(int bits) {
  if (g_session) g_session->fluoro_keys(bits);
}
EMSCRIPTEN_KEEPALIVE const double* cbx_fluoro_frame(int width, int height) {
  return g_session ? g_session->fluoro_frame(width, height).image().header.data() : nullptr;
}
// The same image made on the module's fluoroscopy thread (wasm/fluoro_thread.hpp): the snapshot
// handed to it, the newest image it made returned (0 until one is). The arrays below are then
// that image's.
EMSCRIPTEN_KEEPALIVE const double* cbx_fluoro_request(int width, int height) {
  const cathbox::wasm::FluoroImage* image = g_session ? g_session->fluoro_request(width, height) : nullptr;
  return image ? image->header.data() : nullptr;
}

// Pointers and sizes (elements) of the arrays, 0: vessel vertices, 1: vessel indices, 2: phantom,
// 3: scene floats, 4: scene indices.
EMSCRIPTEN_KEEPALIVE const void* cbx_fluoro_data(int which) {
  const cathbox::wasm::BrowserFluoro* f = fluoro();
  if (f == nullptr) return nullptr;
  switch (which) {
    case 0: return f->vessel_vertices().data();
    case 1: return f->vessel_indices().data();
    case 2: return g_session->fluoro_image().phantom.data();
    case 3: return g_session->fluoro_image().scene_floats.data();
    default: return g_session->fluoro_image().scene_indices.data();
  }
}
EMSCRIPTEN_KEEPALIVE int cbx_fluoro_size(int which) {
  const cathbox::wasm::BrowserFluoro* f = fluoro();
  if (f == nullptr) return 0;
  switch (which) {
    case 0: return static_cast<int>(f->vessel_vertices().size());
    case 1: return static_cast<int>(f->vessel_indices().size());
    case 2: return static_cast<int>(g_session->fluoro_image().phantom.size());
    case 3: return static_cast<int>(g_session->fluoro_image().scene_floats.size());
    default: return static_cast<int>(g_session->fluoro_image().scene_indices.size());
  }
}

// The C-arm panel (BrowserSession::carm_*, the native panel's model): the projections offered as
// JSON; an edit returns 1 posted, 0 nothing changed, -1 refused with cbx_error()'s line; the
// C-arm now (9 doubles: LAO, cranial, SID, table height, field of view, collimation, pulses/s,
// beam on, magnification), from the last cbx_snapshot().
EMSCRIPTEN_KEEPALIVE const char* cbx_carm_projections() {
  g_text = g_session ? g_session->carm_projections_json() : std::string("[]");
  return g_text.c_str();
}
EMSCRIPTEN_KEEPALIVE int cbx_carm_set(int what, double a, double b, double c, double d) {
  if (!g_session) return 0;
  const int done = what == 0   ? g_session->carm_angles(a, b)
                   : what == 1 ? g_session->carm_geometry(a, b, c, d)
                               : g_session->carm_pulse_rate(a);
  g_error = done < 0 ? g_session->carm_error() : std::string();
  return done;
}
EMSCRIPTEN_KEEPALIVE const double* cbx_carm_state() { return g_session ? g_session->carm_state().data() : nullptr; }

// The fluoroscopy's GLSL texts, the native renderer's own (app/fluoro_shaders.hpp), for the page's
// WebGL2 view: 0 the GLSL ES version line, 1 scene vertex, 2 scene fragment, 3 full-viewport
// vertex, 4 composite fragment, 5 scale fragment; null past them.
EMSCRIPTEN_KEEPALIVE const char* cbx_fluoro_shader(int which) {
  namespace glsl = cathbox::app::fluoro_glsl;
  const char* const texts[] = {glsl::kEsVersion,          glsl::kSceneVertex,        glsl::kSceneFragment,
                               glsl::kFullViewportVertex, glsl::kCompositeFragment, glsl::kScaleFragment};
  return which >= 0 && which < static_cast<int>(std::size(texts)) ? texts[which] : nullptr;
}

// The box's command (wasm/browser_box_law.hpp): configured from the box's feature reports, then
// for each command the box's frame (mm, rad from its count zero, minus the session's) and its
// readback (rendered force mN, insertion speed mm/s). cbx_box_command returns CBX_OK (0) with the
// 64 bytes at cbx_box_command_bytes(), or the encoder's status.
EMSCRIPTEN_KEEPALIVE void cbx_box_configure(double full_scale_mN, double slew_mN_per_ms, double period_ms, int mode) {
  if (g_session) g_session->configure_box({full_scale_mN, slew_mN_per_ms, period_ms, static_cast<std::uint8_t>(mode)});
}

EMSCRIPTEN_KEEPALIVE int cbx_box_command(double offset_mm, double offset_rad, double force_mN, double speed_mm_s, int seq,
                                         double time_us, int flags) {
  if (!g_session) return CBX_ERR_STATE;
  cbx_command_report c = g_session->box_command(offset_mm, offset_rad, {force_mN, speed_mm_s});
  c.header.version = CBX_PROTOCOL_VERSION;
  c.header.seq = static_cast<std::uint16_t>(seq);
  c.header.time_us = static_cast<std::uint32_t>(time_us);
  c.flags = static_cast<std::uint8_t>(flags);
  return cbx_command_encode(&c, g_command);
}

EMSCRIPTEN_KEEPALIVE const std::uint8_t* cbx_box_command_bytes() { return g_command; }

// A record (any rig's: native or this page's) replayed here with every state hash checked against
// the collision mesh at mesh_path. 1: every hash matches; 0: a hash differs or the record is bad
// (cbx_error() says which); cbx_summary() then gives {ticks, recorded_ticks, hashes_checked,
// mismatch_tick}. The open run, if any, is left alone.
EMSCRIPTEN_KEEPALIVE int cbx_replay_check(const char* record_path, const char* mesh_path) {
  using namespace cathbox;
  g_error.clear();
  g_text = "null";
  base::Result<vessel::SurfaceMesh> surface = wasm::read_surface_file(mesh_path);
  if (!surface) {
    g_error = surface.error().message;
    return 0;
  }
  base::Result<std::unique_ptr<session::Replay>> replay = session::Replay::open(record_path, true, &*surface);
  if (!replay) {
    g_error = replay.error().message;
    return 0;
  }
  (*replay)->step(-1);
  const session::ReplayResult r = (*replay)->result();
  g_text = "{\"ticks\":" + std::to_string(r.ticks) + ",\"recorded_ticks\":" + std::to_string(r.recorded_ticks) +
           ",\"hashes_checked\":" + std::to_string(r.hashes_checked) +
           ",\"mismatch_tick\":" + (r.mismatch ? std::to_string(r.mismatch->tick) : std::string("null")) + "}";
  if (!r.error.empty()) {
    g_error = r.error;
    return 0;
  }
  if (r.mismatch) {
    g_error = "state hash differs at tick " + std::to_string(r.mismatch->tick);
    return 0;
  }
  return 1;
}

// The last replay's figures (JSON), after cbx_replay_check().
EMSCRIPTEN_KEEPALIVE const char* cbx_replay_summary() { return g_text.c_str(); }

}  // extern "C"

// The worker calls the functions above; main only keeps the runtime alive for them.
int main() { return 0; }
