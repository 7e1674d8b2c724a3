#pragma once
// The session record's byte layout (documented byte by byte in docs/session/record-format.md):
// constants, and the explicit-byte-order writer and reader every part of
// the record is encoded with. All integers are little-endian; varints are LEB128 (unsigned)
// and zigzag LEB128 (signed); doubles are their IEEE-754 binary64 bits as a u64.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::session::record {

inline constexpr std::array<std::uint8_t, 8> kMagic = {'C', 'B', 'X', 'R', 'E', 'C', '\r', '\n'};
// Raised whenever the simulator's results for the same inputs change (the state hashes a record
// carries would no longer replay): 2 since the rod's Newton solve line-searches every update and
// stops on the full step, 3 since an inner tool's clamp pushes back on its carrier's tip and a
// catheter's tip follows the wire from its own tip (issue 29), 13 since a case holds 6 tools and
// the tools entry's mask is a u16, 14 since a planar compressed rod is seeded out of its plane and
// an attached coil's step corrects its stretch and a carried wire's ticks are sub-stepped, 15
// since a rod of under 3 free nodes is not seeded and a carried catheter's or attached coil's
// unconverged tick is sub-stepped, 16 since a holder's first free node fades into the lumen
// friction's path over its first edge, 17 since a compressed rod is seeded out of its plane from
// a strain of 1e-5, not 5e-4, 18 since a seeded or jammed rod starts cold (not every compressed
// one) and a stack steered only by its outermost balloon guide is sub-stepped, 19 since a compressed
// rod too short to seed keeps its warm start and a sheath path keeps the node an inner tool's
// end sits on, 20 since no steering in a balloon guide's stack holds back a wire or a catheter
// its wire steers, a catheter in an aspiration catheter or directly in a balloon guide is steered
// by its wire, and a steered carrier's tip takes its wire's last converged push, 21 since the lumen
// friction's capstan reads an inner tool's free-part push no higher than the free part's external
// forces sum to, 22 since the lumen read blends the radii of the tubes (or centrelines) a point
// lies in (LumenBlend: a stent retriever's expansion no longer steps at a junction), 23 since a
// tool alone in the body bends from the entry point (RodSettings::clamp_hinge_at_entry), 24 since a
// catheter bends from it too and a wholly unsheathed stent retriever is sub-stepped, 25 since a
// carried tool's push on a balloon catheter's tip changes by at most 10 mN a step, 26 since a
// guidewire in a catheter it steers bends from that catheter's tip and its push there is bounded
// too, 27 since a catheter steered while advanced is steered too while a wire or catheter leaving its
// tip is drawn back, 28 since a coil's detachment zone parts over 0.1 s (Simulator::detach), 29
// since a coil bends from its catheter's tip too (not while its joint or pusher is the clamp
// node), 30 since a coil's push on its catheter's turns reacts on that catheter, 31 since a wire
// drawn back bends from its catheter's tip and every guidewire is sub-stepped in up to 8 parts, 32
// since a tool's lumen friction sticks with its shafts' axial compliance (sheath_anchor.hpp), 33 since a wire drawn back walks its hinge to its catheter's tip
// before its first node crossing (Rod::update_window), 34 since the weights stay the clamp
// node's while it walks (Rod::update_weights), 35 since a stent retriever being unsheathed
// from a catheter its wire steers no longer holds that catheter back from sub-steps
// (Simulator::substepped), 36 since the lumen's bending push is the change of the inner tool's
// bending moment, its stiffness over each vertex's span in series (SheathFriction), and a
// carrier's tip push is bounded while a tool leaving it is drawn back (a catheter carrying a
// stent retriever in an aspiration catheter steered too), 37 since a tool's hand force is no more
// than its free part's loads sum to where its clamp takes in the moves after the solve
// (Rod::compute_force_law; the state hashes hold the hand forces), 38 since an unconverged
// tick's hand force and torque are the last converged tick's (Simulator::hold_unconverged), 39
// since a parked carrier steered while advanced keeps its tool's lean on its tip
// (Simulator::tip_lean_held), 40 since that push's slew, while a tool leaving the carrier is
// drawn back into it, is halved at each of its reversals (Simulator::limit_tip_push), 41 since a
// released coil is solved on every second tick over both (tuning::kReleasedCoilTicks), 42 since
// the released coils are solved beside the attached tools, each from where the step began
// (Simulator::launch_released), 43 since a solve that converged on a step it took in part gives
// the hand its linearised equilibrium's force (Rod::hand_force_mN), 44 since a node's normal
// force is zero at the end of a step it ends with no wall plane (Rod::finish_contacts): kept from
// its last contact, it held the node on the next plane it found, 45 since a solve does not
// converge on an iteration that let a node go under more than RodSettings::release_pull_mN, 46
// since a tick reads a released coil whose solve runs beside the next tick as it was when the
// step began (Simulator::released_overlap: its snapshot, hence the state hash, and its metrics).
// An older record is refused in one line, not mis-replayed.
inline constexpr std::uint16_t kFormatVersion = 46;
inline constexpr std::size_t kFileHeaderSize = 16;   // magic, u16 version, u16 0, u32 CRC-32
inline constexpr std::size_t kBlockHeaderSize = 16;  // type, compression, u16 0, u32 stored, u32 raw, u32 CRC-32
inline constexpr std::uint32_t kMaxBlockBytes = 16u << 20;  // stored and raw
inline constexpr std::size_t kTicksPerBlock = 1000;         // and at least one block per second
inline constexpr std::int64_t kBlockSpan_us = 1'000'000;

enum class BlockType : std::uint8_t { kHeader = 'H', kTicks = 'T', kEnd = 'E' };
enum class Compression : std::uint8_t { kNone = 0, kZstd = 1 };

// Per-tick entry kinds 0..15. Controls (control.hpp, kinds 16..127) are entries too: their
// payload is the control's.
enum class EntryKind : std::uint16_t {
  kEndOfTick = 0,  // no length, no payload: the tick is complete
  kTools = 1,      // u16 changed mask (bit 2t: tool t's insertion, 2t+1: its rotation), then one
                   // zigzag varint delta (µm or µrad) per set bit, in bit order
  kStateHash = 2,  // u64 XXH3-64 of the simulation state after this tick's step
  kBoxStatus = 3,  // u8 flags (bit 0 present, bit 1 link up), u16 faults
  kEvent = 4,      // u8 event code (EventCode)
};

enum class EventCode : std::uint8_t {
  kTargetReached = 1,
};

// Why a run ended (the end block).
enum class EndReason : std::uint8_t {
  kStopped = 0,        // the program stopped the session (window closed, restart, destructor)
  kTargetReached = 1,
  kHandFinished = 2,   // the script ended, the autopilot finished, the record replayed
  kEndedByUser = 3,
  kTimeLimit = 4,
};
[[nodiscard]] const char* end_reason_name(EndReason reason);

// Header fields (tags). Tags 64..127 are informational: a reader skips those it does not know;
// any other unknown tag is an error.
enum class HeaderTag : std::uint32_t {
  kSoftwareVersion = 1, kStartUnix_us = 2, kCaseName = 3, kCaseFile = 4, kCaseText = 5,
  kVesselFile = 6, kVesselText = 7, kTool = 8, kEntry = 9, kHeldTool = 10, kHandKind = 11,
  kHandDescription = 12, kDevice = 13, kPeriod_us = 14, kHashEvery = 15,
  kSurfaceFile = 16, kSurfaceBytes = 17,  // a case's own wall (`surface FILE`) and its CBXMESH2 bytes
};
enum class ToolTag : std::uint32_t {
  kName = 1, kKind = 2, kSection = 3, kFriction = 4, kInnerDiameter = 5, kAxialStiffness = 6,
  kDrag = 7, kMaxSpacing = 8, kTipSpacing = 9, kTipZone = 10, kInside = 11, kBloodViscosity = 12,
  kValveFriction = 13,
  kDetach = 14,  // coils: f64, the detachable coil's length (mm)
  kBalloon = 15,  // f64 length, from_tip, nominal, rated burst, then (pressure, diameter) pairs
  kNextCoil = 16,  // coils: a next coil, in order, as a section (5 doubles, 7 with its shape)
  kStentRetriever = 17,  // push wires: f64 diameter mm, length mm, embedding time s
};
enum class DeviceTag : std::uint32_t {
  kDescription = 1, kSerial = 2, kBoard = 3, kFirmware = 4, kInsertionCountsPerM = 5,
  kRotationCountsPerRev = 6, kInsertionFullScaleMn = 7, kRotationFullScaleUnm = 8,
  kInsertionActuator = 9, kRotationActuator = 10,
};
// 64: the haptic ticks a real-time run dropped (u64), in the range an older reader skips.
enum class EndTag : std::uint32_t { kReason = 1, kReasonText = 2, kTicks = 3, kEndUnix_us = 4, kHapticDropped = 64 };

[[nodiscard]] std::uint32_t crc32(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b = {});

// Appends to a byte vector (which the caller may reserve).
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v);
  void u32(std::uint32_t v);
  void u64(std::uint64_t v);
  void f64(double v);
  void varint(std::uint64_t v);
  void zigzag(std::int64_t v) { varint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63)); }
  void bytes(std::span<const std::uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
  void text(std::string_view s) { bytes({reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}); }
  // A tagged field: varint tag, varint length, the bytes.
  void field(std::uint32_t tag, std::span<const std::uint8_t> b);
  void field_text(std::uint32_t tag, std::string_view s);
  void field_u64(std::uint32_t tag, std::uint64_t v);
  void field_f64(std::uint32_t tag, double v);
  [[nodiscard]] std::size_t size() const { return out_.size(); }

 private:
  std::vector<std::uint8_t>& out_;
};

// Reads from a byte span; every read checks the bounds and fails (returns false) past the end.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> in) : in_(in) {}
  [[nodiscard]] bool u8(std::uint8_t& v);
  [[nodiscard]] bool u16(std::uint16_t& v);
  [[nodiscard]] bool u32(std::uint32_t& v);
  [[nodiscard]] bool u64(std::uint64_t& v);
  [[nodiscard]] bool f64(double& v);
  [[nodiscard]] bool varint(std::uint64_t& v);
  [[nodiscard]] bool zigzag(std::int64_t& v);
  [[nodiscard]] bool bytes(std::size_t n, std::span<const std::uint8_t>& out);
  [[nodiscard]] std::size_t position() const { return pos_; }
  [[nodiscard]] std::size_t left() const { return in_.size() - pos_; }
  [[nodiscard]] bool done() const { return pos_ == in_.size(); }

 private:
  template <class T>
  [[nodiscard]] bool fixed(T& v);
  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
};

}  // namespace cathbox::session::record
