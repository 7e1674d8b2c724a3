#include "centre_load.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/auth.hpp"
#include "server/case_library.hpp"
#include "server/client.hpp"
#include "server/migrations.hpp"
#include "server/password_hasher.hpp"
#include "server/sha256.hpp"
#include "server/testing/server_process.hpp"
#include "session/scripted_hand.hpp"
#include "session/session.hpp"
#include "session/session_case.hpp"

namespace cathbox::server::bench {

namespace {

using Clock = std::chrono::steady_clock;
using json = nlohmann::json;

const Clock::time_point kEpoch = Clock::now();

std::int64_t now_us() { return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - kEpoch).count(); }

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::int64_t rss_kb(int pid, const char* field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stoll(line.substr(std::string(field).size()));
  }
  return 0;
}

// Session records of the y-bifurcation case driven by the scripted hand, as trainers upload
// them: `count` different runs (1.0 s to ~2.5 s of simulated time), each the bytes of a
// closed *.cbxrec file.
std::vector<std::string> make_records(int count) {
  const std::string folder = std::filesystem::temp_directory_path() / ("cathbox-bench-records-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) {
    auto scene = session::load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
    if (!scene) throw std::runtime_error(scene.error().message);
    auto hand = std::make_unique<session::ScriptedHand>(scene.value()->route_mm, scene.value()->spec.tools.front().length_mm());
    hand->set_tick_s(1e-3);
    session::Session run(std::move(scene.value()), std::move(hand));
    const std::string path = folder + "/run" + std::to_string(i) + ".cbxrec";
    if (const base::Status<> recording = run.record_to(path); !recording) throw std::runtime_error(recording.error().message);
    run.step_virtual(1000 + 31 * i);
    run.end_run();
    run.step_virtual(1);
    if (!run.recorder()->close()) throw std::runtime_error(path + ": cannot close the record");
    out.push_back(read_text(path));
  }
  std::filesystem::remove_all(folder);
  return out;
}

// A frame as a trainer sends it: two tools of `nodes` points, tip, forces, contacts, metrics.
// Built once per rig; seq and sent_us are written in per push.
struct FrameTemplate {
  std::string before_seq, between, after_sent;
  explicit FrameTemplate(int rig, int nodes) {
    json tools = json::array();
    for (const char* name : {"catheter", "guidewire"}) {
      json pts = json::array();
      for (int i = 0; i < nodes; ++i) {
        const double t = i * 0.37 + rig;
        pts.push_back({std::round(10 * std::sin(t) * 100) / 100, std::round(10 * std::cos(t) * 100) / 100, std::round((-80 + i * 2.5) * 100) / 100});
      }
      tools.push_back({{"name", name}, {"nodes_mm", pts}});
    }
    json body = {{"t_ms", 1234.5},
                 {"tools", tools},
                 {"tip_mm", {1.25, -3.5, 80.75}},
                 {"forces", {{"tip_mN", 41.2}, {"wall_peak_mN", 96.0}, {"hand_mN", 120.5}}},
                 {"contacts", json::array({{{"p_mm", {1.0, 2.0, 3.0}}, {"f_mN", 12.5}}, {{"p_mm", {4.0, 5.0, 6.0}}, {"f_mN", 7.25}}})},
                 {"fluoro", {{"on", true}, {"time_s", 31.5}}},
                 {"metrics", {{"path_length_mm", 402.1}, {"wall_contacts", 3}, {"peak_wall_force_mN", 96.0}}}};
    std::string text = body.dump();
    text.pop_back();  // the closing brace
    before_seq = R"({"type":"frame","seq":)";
    between = ",\"sent_us\":";
    after_sent = "," + text.substr(1) + "}";
  }
  std::string make(std::int64_t seq, std::int64_t sent) const {
    return before_seq + std::to_string(seq) + between + std::to_string(sent) + after_sent;
  }
};

struct Shared {
  std::atomic<bool> stop{false};
  std::atomic<bool> measuring{false};
  std::mutex mutex;
  LoadFigures figures;
  std::map<std::string, std::string> acknowledged;  // case name -> content hash
};

void sleep_until(Clock::time_point t, const Shared& s) {
  while (!s.stop && Clock::now() < t) std::this_thread::sleep_for(std::min<Clock::duration>(t - Clock::now(), std::chrono::milliseconds(50)));
}

}  // namespace

LoadFigures run_centre_load(const std::string& db_url, bool two_instances, const LoadOptions& o) {
  // Accounts (light Argon2 parameters: the load is about the API, not password hashing) and
  // the case the rigs run.
  {
    DatabaseOpen opened = open_database(db_url);
    if (!opened.db) throw std::runtime_error(opened.error);
    if (!migrate(*opened.db)) throw std::runtime_error("migration failed");
    Store store(std::move(opened.db));
    SystemClock clock;
    Auth auth(store, clock, PasswordHasher(test_argon2_params()));
    for (int w = 0; w < o.watchers; ++w) (void)auth.create_user("teacher" + std::to_string(w), Role::kInstructor, "password-123");
    for (int r = 0; r < o.rigs; ++r) (void)auth.create_user("trainee" + std::to_string(r), Role::kTrainee, "password-123");
    CaseBundle b;
    b.case_file = "y_bifurcation.case";
    b.case_text = read_text(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
    b.hclm_file = "y_bifurcation.hclm";
    b.hclm_text = read_text(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm");
    CaseLibrary library(store);
    if (!library.upload("ybif", b, std::nullopt, clock.now_us())) throw std::runtime_error("seeding the case failed");
  }
  // Every client logs in from 127.0.0.1: lift the per-address login throttle for the run.
  std::vector<std::string> args = {"--api-threads", "4", "--login-burst", "1000"};
  args.insert(args.end(), o.server_args.begin(), o.server_args.end());
  testing::ServerProcess a(db_url, 0, args);
  std::unique_ptr<testing::ServerProcess> b_owner;
  if (two_instances) b_owner = std::make_unique<testing::ServerProcess>(db_url, 0, args);
  testing::ServerProcess& b = two_instances ? *b_owner : a;

  Shared s;
  const auto token = [](const std::string& base, const std::string& name) {
    ServerClient c(base);
    if (!c.login(name, "password-123")) throw std::runtime_error("login " + name);
    return c.token();
  };
  std::vector<std::string> rig_tokens, teacher_tokens;
  for (int r = 0; r < o.rigs; ++r) rig_tokens.push_back(token(a.base_url(), "trainee" + std::to_string(r)));
  for (int w = 0; w < o.watchers; ++w) teacher_tokens.push_back(token(b.base_url(), "teacher" + std::to_string(w)));

  std::vector<std::thread> threads;
  // Watchers: each watches rigs_per_watcher consecutive rigs (wrapping).
  for (int w = 0; w < o.watchers; ++w) {
    std::string rigs;
    for (int k = 0; k < o.rigs_per_watcher; ++k) rigs += (k ? "," : "") + ("rig-" + std::to_string((w * o.rigs / o.watchers + k) % o.rigs));
    threads.emplace_back([&s, &b, w, rigs, tok = teacher_tokens[static_cast<std::size_t>(w)]] {
      WsClient ws(10000);
      if (!ws.connect(b.base_url(), "/api/v1/live/watch?rigs=" + rigs, tok)) return;
      std::vector<double> latencies;
      std::int64_t delivered = 0;
      while (!s.stop) {
        const Result<std::string> m = ws.read(200);
        if (!m) {
          if (m.error().message == WsClient::kReadTimeout) continue;
          break;
        }
        const std::int64_t arrived = now_us();
        // The frame's sent_us without parsing the whole message.
        const std::size_t at = m->find("\"sent_us\":");
        if (at == std::string::npos || !s.measuring) continue;
        const std::int64_t sent = std::stoll(m->substr(at + 10, 24));
        latencies.push_back(static_cast<double>(arrived - sent) / 1000.0);
        ++delivered;
      }
      (void)w;
      std::lock_guard lock(s.mutex);
      s.figures.stream_ms.insert(s.figures.stream_ms.end(), latencies.begin(), latencies.end());
      s.figures.frames_delivered += delivered;
    });
  }
  // Rigs.
  std::vector<std::unique_ptr<LiveStream>> streams;
  std::vector<FrameTemplate> frames;
  for (int r = 0; r < o.rigs; ++r) {
    streams.push_back(std::make_unique<LiveStream>(
        LiveStream::Options{a.base_url(), rig_tokens[static_cast<std::size_t>(r)], "rig-" + std::to_string(r), "ybif", 0, std::nullopt, 500}));
    frames.emplace_back(r, o.tool_nodes);
  }
  s.figures.frame_bytes = static_cast<std::int64_t>(frames[0].make(1000, now_us()).size());
  threads.emplace_back([&] {
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.frame_hz));
    auto next = Clock::now();
    std::int64_t seq = 0, pushed = 0;
    while (!s.stop) {
      ++seq;
      for (std::size_t r = 0; r < streams.size(); ++r) {
        streams[r]->push(frames[r].make(seq, now_us()));
        if (s.measuring) ++pushed;
      }
      next += period;
      sleep_until(next, s);
    }
    std::lock_guard lock(s.mutex);
    s.figures.frames_pushed = pushed;
  });
  // Instructors' API calls.
  for (int w = 0; w < o.watchers; ++w) {
    threads.emplace_back([&s, &b, &o, tok = teacher_tokens[static_cast<std::size_t>(w)], w] {
      HttpClient http(b.base_url(), 10000);
      http.set_token(tok);
      const std::vector<std::string> targets = {"/api/v1/live/rigs", "/api/v1/results?limit=20", "/api/v1/cases", "/api/v1/assignments",
                                                "/api/v1/me", "/api/v1/users"};
      const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.api_per_watcher_hz));
      auto next = Clock::now() + period * w / o.watchers;
      std::vector<double> ms;
      std::int64_t errors = 0;
      for (std::size_t i = static_cast<std::size_t>(w); !s.stop; ++i) {
        sleep_until(next, s);
        next += period;
        const auto t0 = Clock::now();
        const HttpAnswer answer = http.get(targets[i % targets.size()]);
        const double elapsed = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        if (!s.measuring) continue;
        ms.push_back(elapsed);
        if (answer.status != 200) ++errors;
      }
      std::lock_guard lock(s.mutex);
      s.figures.api_ms.insert(s.figures.api_ms.end(), ms.begin(), ms.end());
      s.figures.api_errors += errors;
    });
  }
  // Session records uploaded by trainees (each replayed by the server before it is stored),
  // retried until acknowledged; each is checked in the database afterwards.
  const int record_count = static_cast<int>(std::ceil(o.uploaders * o.uploads_per_uploader_hz * (o.warmup_s + o.measure_s + 2)));
  const std::vector<std::string> records = make_records(record_count);
  std::atomic<int> next_record{0};
  for (int u = 0; u < o.uploaders; ++u) {
    threads.emplace_back([&, u] {
      ServerClient client(a.base_url(), 30000);
      client.set_token(token(a.base_url(), "trainee" + std::to_string(u % o.rigs)));
      const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.uploads_per_uploader_hz));
      auto next = Clock::now();
      std::int64_t attempted = 0;
      while (!s.stop) {
        sleep_until(next, s);
        next += period;
        const int i = next_record++;
        if (s.stop || i >= static_cast<int>(records.size())) break;
        ++attempted;
        for (int attempt = 0; attempt < 5 && !s.stop; ++attempt) {
          const UploadOutcome r = client.upload_record(records[static_cast<std::size_t>(i)], std::nullopt);
          if (r.verdict == UploadVerdict::kStored || r.verdict == UploadVerdict::kDuplicate) {
            std::lock_guard lock(s.mutex);
            s.acknowledged["record" + std::to_string(i)] = sha256_hex(records[static_cast<std::size_t>(i)]);
            break;
          }
          if (r.verdict == UploadVerdict::kRefused) throw std::runtime_error("record " + std::to_string(i) + " refused: " + r.message);
        }
      }
      std::lock_guard lock(s.mutex);
      s.figures.uploads_attempted += attempted;
    });
  }

  // Warm up, then measure; sample the servers' memory every half second.
  const auto sample = [&](int pid) { return rss_kb(pid, "VmRSS:"); };
  std::this_thread::sleep_for(std::chrono::seconds(o.warmup_s));
  s.figures.rss_after_warmup_kb = sample(a.pid()) + (two_instances ? sample(b.pid()) : 0);
  s.measuring = true;
  const auto end = Clock::now() + std::chrono::seconds(o.measure_s);
  while (Clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    s.figures.rss_peak_kb = std::max(s.figures.rss_peak_kb, sample(a.pid()) + (two_instances ? sample(b.pid()) : 0));
  }
  s.measuring = false;
  s.figures.rss_end_kb = sample(a.pid()) + (two_instances ? sample(b.pid()) : 0);
  s.stop = true;
  for (auto& t : threads) t.join();
  streams.clear();

  // No lost uploads: every acknowledged one is in the database.
  DatabaseOpen opened = open_database(db_url);
  Store store(std::move(opened.db));
  s.figures.uploads_acknowledged = static_cast<std::int64_t>(s.acknowledged.size());
  for (const auto& [name, hash] : s.acknowledged) {
    if (store.result_by_hash(hash)) ++s.figures.uploads_verified;
  }
  return s.figures;
}

}  // namespace cathbox::server::bench
