#pragma once
// Real session records for the server's tests: the y-bifurcation's left branch by action script,
// recorded in virtual time (the scene may be changed first: another entry, other tools), and the
// same bytes rewritten as an uploader could: re-encoded (blocks stored uncompressed, an extra
// informational header field) or cut (no end block).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "server/zstd_codec.hpp"
#include "session/action_script_hand.hpp"
#include "session/record_format.hpp"
#include "session/session.hpp"

namespace cathbox::server::test {

// A folder of this process's own: CTest runs a program's SQLite and PostgreSQL variants at once.
inline std::string scratch(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::path(CATHBOX_BINARY_DIR) / ("server_records_test." + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

inline std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The y-bifurcation's left branch by action script, recorded in virtual time; `change` edits the
// scene before the session starts (the record then carries what was simulated). Its path.
inline std::string record_left_branch(const std::function<void(session::SessionCase&)>& change = {},
                                      const std::string& name = "left.cbxrec") {
  const std::string path = scratch(name);
  auto scene = session::load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
  EXPECT_TRUE(scene) << scene.error().message;
  std::string error;
  auto script = session::ActionScriptHand::load(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation_left.actions",
                                                *scene.value());
  EXPECT_TRUE(script) << (script ? "" : script.error().message);
  std::unique_ptr<session::Hand> hand;
  if (script) hand = std::move(*script);
  if (change) change(*scene.value());
  session::Session s(std::move(scene.value()), std::move(hand));
  const base::Status<> recording = s.record_to(path);
  EXPECT_TRUE(recording) << recording.error().message;
  while (!s.over()) s.step_virtual(1000);
  EXPECT_TRUE(s.recorder()->close());
  return path;
}

// The case at `case_path` driven by the action script at `actions`, recorded in virtual time to
// `case_path`.cbxrec: the record's bytes (empty when the case or script does not load).
inline std::string record_by_script(const std::string& case_path, const std::string& actions) {
  auto scene = session::load_session_case(case_path);
  EXPECT_TRUE(scene) << scene.error().message;
  if (!scene) return {};
  auto script = session::ActionScriptHand::load(actions, *scene.value());
  EXPECT_TRUE(script) << (script ? "" : script.error().message);
  if (!script) return {};
  session::Session s(std::move(scene.value()), std::move(*script));
  const std::string path = case_path + ".cbxrec";
  const base::Status<> recording = s.record_to(path);
  EXPECT_TRUE(recording) << recording.error().message;
  while (!s.over()) s.step_virtual(1000);
  EXPECT_TRUE(s.recorder()->close());
  return read_all(path);
}

namespace detail {
inline std::uint32_t u32_at(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}
}  // namespace detail

// The record without its end block, as a killed recorder leaves it.
inline std::string cut_before_end(const std::string& record) {
  std::size_t at = session::record::kFileHeaderSize;
  while (at + session::record::kBlockHeaderSize <= record.size()) {
    if (record[at] == static_cast<char>(session::record::BlockType::kEnd)) return record.substr(0, at);
    at += session::record::kBlockHeaderSize + detail::u32_at(record, at + 4);
  }
  return record;
}

// The same run encoded otherwise: every block stored uncompressed, and the header block with an
// extra informational field (tag 100: readers skip tags 64-127 they do not know).
inline std::string reencoded(const std::string& record) {
  namespace rf = session::record;
  std::string out = record.substr(0, rf::kFileHeaderSize);
  std::size_t at = rf::kFileHeaderSize;
  while (at + rf::kBlockHeaderSize <= record.size()) {
    const std::uint32_t stored = detail::u32_at(record, at + 4);
    const std::uint32_t raw = detail::u32_at(record, at + 8);
    std::string data = record.substr(at + rf::kBlockHeaderSize, stored);
    if (record[at + 1] == 1) {
      Result<std::string> plain = zstd_decompress(data, raw);
      EXPECT_TRUE(plain) << plain.error().message;
      data = plain.value();
    }
    if (record[at] == static_cast<char>(rf::BlockType::kHeader)) data += std::string("\x64\x05hello", 7);
    std::string head = record.substr(at, rf::kBlockHeaderSize);
    head[1] = 0;
    const auto size = static_cast<std::uint32_t>(data.size());
    std::memcpy(head.data() + 4, &size, 4);
    std::memcpy(head.data() + 8, &size, 4);
    const auto* h = reinterpret_cast<const std::uint8_t*>(head.data());
    const auto* d = reinterpret_cast<const std::uint8_t*>(data.data());
    const std::uint32_t crc = rf::crc32({h, 12}, {d, data.size()});
    std::memcpy(head.data() + 12, &crc, 4);
    out += head + data;
    at += rf::kBlockHeaderSize + stored;
  }
  return out;
}

}  // namespace cathbox::server::test
