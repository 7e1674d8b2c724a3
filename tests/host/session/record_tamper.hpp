#pragma once
// Test helper: rewrites a record with the first tool's insertion 1 um further from `from_tick`
// on (header, controls and recorded hashes kept), so a replay must fail at the next hash.
// Used by the session tests and the server's record tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "session/record_reader.hpp"
#include "session/recorder.hpp"

namespace cathbox::session::testing {

inline void tamper_record(const std::string& in_path, const std::string& out_path, std::int64_t from_tick) {
  std::string error;
  auto in_opened = RecordReader::open(in_path);
  ASSERT_TRUE(in_opened) << in_opened.error().message;
  auto in = std::move(*in_opened);
  auto created = Recorder::create(out_path, in->header());
  ASSERT_TRUE(created) << created.error().message;
  auto& out = *created;
  TickRecord t;
  TickInput input;
  input.tool_count = in->header().tools.size();
  while (in->next(t)) {
    out->begin_tick(t.tick, t.tick * 1000);
    for (std::size_t i = 0; i < t.control_count; ++i) out->control(t.controls[i]);
    input.tools = t.tools;
    if (t.tick >= from_tick) input.tools[0].insertion_um += 1;
    out->tools(input);
    if (t.state_hash) out->state_hash(*t.state_hash);
    out->end_tick();
  }
  EXPECT_TRUE(out->close());
}

}  // namespace cathbox::session::testing
