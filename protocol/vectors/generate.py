#!/usr/bin/env python3
"""Generates the golden vectors (cbx_vectors.c and VECTORS.md) from an independent Python
encoding of protocol v1. The C codecs must decode these bytes to these values and re-encode
them byte for byte (tests/protocol). Run: python3 protocol/vectors/generate.py"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


# Field layouts: (name, struct format, offset). Offsets are bytes from the report start.
HEADER = [("header.seq", "<H", 2), ("header.time_us", "<I", 4)]
LAW = [("offset", "<i", 0), ("pos0", "<i", 4), ("stiffness", "<i", 8), ("damping", "<i", 12),
       ("out_min", "<i", 16), ("out_max", "<i", 20)]
LAYOUTS = {
    "state": (0x01, "cbx_state_report", [
        ("insertion_count", "<i", 8), ("rotation_count", "<i", 12),
        ("insertion_vel_cps", "<i", 16), ("rotation_vel_cps", "<i", 20),
        ("insertion_force_mN", "<i", 24), ("rotation_torque_uNm", "<i", 28),
        ("insertion_current_mA", "<h", 32), ("rotation_current_mA", "<h", 34),
        ("status", "<H", 36), ("faults", "<H", 38), ("command_seq_echo", "<H", 40),
        ("encoder_errors", "<H", 42), ("rx_errors", "<H", 44), ("mode", "<B", 46),
        ("board_faults", "<B", 47), ("in_dropped", "<H", 48)]),
    "command": (0x02, "cbx_command_report", [("mode", "<B", 8), ("flags", "<B", 9)]
                + [("insertion." + n, f, 12 + o) for n, f, o in LAW]
                + [("rotation." + n, f, 36 + o) for n, f, o in LAW]),
    "device_info": (0x10, "cbx_device_info", [
        ("fw_major", "<B", 8), ("fw_minor", "<B", 9), ("fw_patch", "<B", 10),
        ("protocol_minor", "<B", 11), ("serial", "16s", 12), ("board", "16s", 28),
        ("insertion_actuator", "<B", 44), ("rotation_actuator", "<B", 45),
        ("insertion_encoder_cpr", "<I", 46), ("rotation_encoder_cpr", "<I", 50),
        ("build", "8s", 54)]),
    "calibration": (0x11, "cbx_calibration", [
        ("insertion_counts_per_m", "<I", 8), ("rotation_counts_per_rev", "<I", 12),
        ("insertion_full_scale_mN", "<I", 16), ("rotation_full_scale_uNm", "<I", 20)]
        + [(f"insertion_curve[{i}].{k}", "<H", 24 + 4 * i + 2 * j)
           for i in range(4) for j, k in enumerate(["in_permille", "out_permille"])]
        + [(f"rotation_curve[{i}].{k}", "<H", 40 + 4 * i + 2 * j)
           for i in range(4) for j, k in enumerate(["in_permille", "out_permille"])]),
    "limits": (0x12, "cbx_limits", [
        ("max_force_mN", "<I", 8), ("max_torque_uNm", "<I", 12), ("watchdog_timeout_ms", "<H", 16),
        ("insertion_max_current_mA", "<H", 18), ("rotation_max_current_mA", "<H", 20),
        ("force_slew_mN_per_ms", "<H", 22), ("torque_slew_uNm_per_ms", "<H", 24)]),
    "reset_counters": (0x13, "cbx_reset_counters", [("mask", "<B", 8)]),
    "enter_bootloader": (0x14, "cbx_enter_bootloader", [("magic", "<I", 8)]),
    "selftest": (0x15, "cbx_selftest", [
        ("state", "<B", 8), ("failed_checks", "<H", 10), ("insertion_current_mA", "<h", 12),
        ("rotation_current_mA", "<h", 14), ("supply_mV", "<H", 16)]),
}


def encode(kind, values):
    rid, _, fields = LAYOUTS[kind]
    out = bytearray(64)
    out[0] = rid
    out[1] = 1
    for name, fmt, off in HEADER + fields:
        v = values.get(name, 0)
        if fmt.endswith("s"):
            v = v.encode("ascii")
        struct.pack_into(fmt, out, off, v)
    struct.pack_into("<H", out, 62, crc16(out[:62]))
    return bytes(out)


# The firmware image info block (64 bytes at image offset 0x200; not a report: no ID, version
# byte or CRC).
IMAGE_INFO = [("fw_major", "<B", 6), ("fw_minor", "<B", 7), ("fw_patch", "<B", 8),
              ("protocol_minor", "<B", 9), ("board", "16s", 12), ("build", "8s", 28),
              ("image_size", "<I", 60)]


def encode_image_info(values, magic=0x49584243, layout=1, size=64):
    out = bytearray(64)
    struct.pack_into("<IBB", out, 0, magic, layout, size)
    for name, fmt, off in IMAGE_INFO:
        v = values.get(name, 0)
        if fmt.endswith("s"):
            v = v.encode("ascii")
        struct.pack_into(fmt, out, off, v)
    return bytes(out)


IDENTITY = {}
for axis in ("insertion", "rotation"):
    for i, (a, b) in enumerate([(250, 250), (500, 500), (750, 750), (1000, 1000)]):
        IDENTITY[f"{axis}_curve[{i}].in_permille"] = a
        IDENTITY[f"{axis}_curve[{i}].out_permille"] = b
BRAKE_CURVE = {}
for axis in ("insertion", "rotation"):
    for i, (a, b) in enumerate([(100, 180), (300, 390), (600, 650), (1000, 1000)]):
        BRAKE_CURVE[f"{axis}_curve[{i}].in_permille"] = a
        BRAKE_CURVE[f"{axis}_curve[{i}].out_permille"] = b

# Good vectors: (name, kind, values, description)
GOOD = [
    ("state_idle", "state", {"header.seq": 1, "header.time_us": 1000, "status": 0x02,
                             "mode": 0}, "powered, calibrated, outputs off, nothing moving"),
    ("state_pushing", "state", {
        "header.seq": 0xBEEF, "header.time_us": 0xFFFFFF00, "insertion_count": 123456,
        "rotation_count": -2048, "insertion_vel_cps": 4000, "rotation_vel_cps": -512,
        "insertion_force_mN": -350, "rotation_torque_uNm": 1200, "insertion_current_mA": 410,
        "rotation_current_mA": -35, "status": 0x0B, "faults": 0, "command_seq_echo": 0x1234,
        "encoder_errors": 3, "rx_errors": 1, "mode": 1, "in_dropped": 2},
     "brake mode, wire being pushed in while twisted back, 350 mN resisting"),
    ("state_faults", "state", {
        "header.seq": 0, "header.time_us": 0x80000000, "insertion_count": -1,
        "rotation_count": 2147483647, "status": 0x04, "faults": 0x3F, "command_seq_echo": 0xFFFF,
        "encoder_errors": 65535, "rx_errors": 65535, "mode": 0, "board_faults": 0x01,
        "in_dropped": 65535},
     "every fault latched, the crystal failed, E-stop pressed, counters saturated"),
    ("command_brake_law", "command", {
        "header.seq": 0x1234, "header.time_us": 5000000, "mode": 1, "flags": 0,
        "insertion.offset": -200, "insertion.pos0": 250000, "insertion.stiffness": 400000,
        "insertion.damping": 2000, "insertion.out_min": -3000, "insertion.out_max": 0,
        "rotation.offset": 0, "rotation.pos0": -1570796, "rotation.stiffness": 5000,
        "rotation.damping": 50, "rotation.out_min": -2000, "rotation.out_max": 2000},
     "brake mode; a wall 400 N/m stiff at 250 mm of insertion, 200 mN of friction"),
    ("command_off_ack", "command", {"header.seq": 7, "header.time_us": 7000, "mode": 0,
                                    "flags": 1},
     "outputs off, acknowledge latched faults"),
    ("command_motor_push", "command", {
        "header.seq": 65535, "header.time_us": 4294967295, "mode": 2,
        "insertion.offset": 1500, "insertion.out_min": -5000, "insertion.out_max": 5000,
        "rotation.offset": -300, "rotation.out_min": -1000, "rotation.out_max": 1000},
     "motor mode, constant 1.5 N push and -300 uNm twist; sequence and time about to wrap"),
    ("device_info", "device_info", {
        "header.seq": 1, "header.time_us": 250, "fw_major": 1, "fw_minor": 2, "fw_patch": 3,
        "protocol_minor": 1, "serial": "CBX-0001", "board": "stm32f411-bp",
        "insertion_actuator": 1, "rotation_actuator": 1, "insertion_encoder_cpr": 2400,
        "rotation_encoder_cpr": 4096, "build": "4cff6b7"},
     "a brake box with a 600-line and a 1024-line encoder, firmware built from commit 4cff6b7"),
    ("calibration_identity", "calibration", dict({
        "header.seq": 2, "header.time_us": 500, "insertion_counts_per_m": 38197,
        "rotation_counts_per_rev": 4096, "insertion_full_scale_mN": 8000,
        "rotation_full_scale_uNm": 20000}, **IDENTITY),
     "38.197 counts/mm roller (20 mm diameter, 2400 cpr), linear output curves"),
    ("calibration_brake", "calibration", dict({
        "header.seq": 3, "header.time_us": 750, "insertion_counts_per_m": 40000,
        "rotation_counts_per_rev": 8192, "insertion_full_scale_mN": 12000,
        "rotation_full_scale_uNm": 15000}, **BRAKE_CURVE),
     "magnetic-particle brake curve: more drive needed at low torque"),
    ("calibration_none", "calibration", {"header.seq": 4, "header.time_us": 1000},
     "not calibrated: zero counts, flat zero curve is invalid so curves are identity"),
    ("limits_default", "limits", {
        "header.seq": 5, "header.time_us": 1250, "max_force_mN": 5000, "max_torque_uNm": 50000,
        "watchdog_timeout_ms": 50, "insertion_max_current_mA": 1500,
        "rotation_max_current_mA": 1000, "force_slew_mN_per_ms": 100,
        "torque_slew_uNm_per_ms": 1000}, "the firmware's defaults"),
    ("reset_counters_all", "reset_counters", {"header.seq": 6, "header.time_us": 1500,
                                              "mask": 7}, "zero both counts and the error counters"),
    ("enter_bootloader", "enter_bootloader", {"header.seq": 7, "header.time_us": 1750,
                                              "magic": 0xB00710AD}, "detach into the ROM DFU bootloader"),
    ("selftest_start", "selftest", {"header.seq": 8, "header.time_us": 2000, "state": 1},
     "host asks for a self-test"),
    ("selftest_failed", "selftest", {
        "header.seq": 9, "header.time_us": 2250, "state": 3, "failed_checks": 0x14,
        "insertion_current_mA": 3, "rotation_current_mA": 180, "supply_mV": 11900},
     "insertion actuator draws no current and the E-stop loop is open"),
]
# calibration_none must still carry valid (increasing) curves.
GOOD[9][2].update(IDENTITY)


def mutate(data, **changes):
    b = bytearray(data)
    for off, val in changes.get("set", []):
        b[off] = val
    if changes.get("fix_crc"):
        struct.pack_into("<H", b, 62, crc16(b[:62]))
    return bytes(b)


by_name = {n: encode(k, v) for n, k, v, _ in GOOD}
kinds = {n: k for n, k, _, _ in GOOD}
# Bad vectors: (name, decoder kind, bytes, expected status, description)
BAD = [
    ("bad_length_63", "state", by_name["state_pushing"][:63], "CBX_ERR_LENGTH",
     "one byte short"),
    ("bad_report_id", "state", by_name["command_brake_law"], "CBX_ERR_REPORT_ID",
     "a command offered to the state decoder"),
    ("bad_version_2", "state", mutate(by_name["state_idle"], set=[(1, 2)], fix_crc=True),
     "CBX_ERR_VERSION", "a protocol v2 box: incompatible, whatever the CRC"),
    ("bad_crc", "command", mutate(by_name["command_brake_law"], set=[(20, 0x55)]),
     "CBX_ERR_CRC", "one payload byte changed in transit"),
    ("bad_mode", "command", mutate(by_name["command_off_ack"], set=[(8, 3)], fix_crc=True),
     "CBX_ERR_RANGE", "mode 3 does not exist"),
    ("bad_law_min_max", "command",
     mutate(by_name["command_motor_push"], set=[(28, 0x89), (29, 0x13), (30, 0x00), (31, 0x00)],
            fix_crc=True), "CBX_ERR_RANGE", "insertion out_min 5001 above out_max 5000"),
    ("bad_status_bits", "state", mutate(by_name["state_idle"], set=[(37, 0x80)], fix_crc=True),
     "CBX_ERR_RANGE", "undefined status bit 15"),
    ("bad_serial_padding", "device_info",
     mutate(by_name["device_info"], set=[(25, 0x41)], fix_crc=True), "CBX_ERR_RANGE",
     "text after the serial's NUL padding"),
    ("bad_curve_order", "calibration",
     mutate(by_name["calibration_identity"], set=[(28, 0xFA), (29, 0x00)], fix_crc=True),
     "CBX_ERR_RANGE", "insertion curve input not increasing (250 then 250)"),
    ("bad_watchdog_range", "limits",
     mutate(by_name["limits_default"], set=[(16, 0x00), (17, 0x00)], fix_crc=True),
     "CBX_ERR_RANGE", "a zero watchdog timeout"),
    ("bad_bootloader_magic", "enter_bootloader",
     mutate(by_name["enter_bootloader"], set=[(8, 0)], fix_crc=True), "CBX_ERR_RANGE",
     "a wrong magic word must not reboot the box"),
    ("bad_board_faults", "state", mutate(by_name["state_idle"], set=[(47, 0x02)], fix_crc=True),
     "CBX_ERR_RANGE", "undefined board fault bit 1"),
    ("bad_build_padding", "device_info",
     mutate(by_name["device_info"], set=[(60, 0x00), (61, 0x41)], fix_crc=True), "CBX_ERR_RANGE",
     "text after the build identifier's NUL padding"),
]

IMAGE_1_1 = {"fw_major": 1, "fw_minor": 1, "fw_patch": 0, "protocol_minor": 1,
             "board": "stm32f411-bp", "build": "4cff6b7", "image_size": 17024}
# Image info vectors: (name, bytes, expected status, values, description)
IMAGE_VECTORS = [
    ("image_info_1_1_0", encode_image_info(IMAGE_1_1), "CBX_OK", IMAGE_1_1,
     "firmware 1.1.0 for the Black Pill, 17024 bytes, built from commit 4cff6b7"),
    ("image_info_bad_magic", encode_image_info(IMAGE_1_1, magic=0xFFFFFFFF), "CBX_ERR_REPORT_ID",
     None, "erased flash where the block should be: no info block"),
    ("image_info_bad_layout", encode_image_info(IMAGE_1_1, layout=2), "CBX_ERR_VERSION", None,
     "a block layout this reader does not know"),
    ("image_info_bad_size", encode_image_info(dict(IMAGE_1_1, image_size=0x200)), "CBX_ERR_RANGE",
     None, "an image that ends before its own info block"),
    ("image_info_no_board", encode_image_info(dict(IMAGE_1_1, board="")), "CBX_ERR_RANGE", None,
     "no board name"),
]


def c_bytes(data):
    rows = []
    for i in range(0, len(data), 16):
        rows.append("      " + ", ".join(f"0x{b:02X}" for b in data[i:i + 16]) + ",")
    return "\n".join(rows)


def c_value(kind, values):
    _, ctype, fields = LAYOUTS[kind]
    parts = [f".header = {{1, {values.get('header.seq', 0)}u, {values.get('header.time_us', 0)}u}}"]
    for name, fmt, _ in fields:
        v = values.get(name, 0)
        if fmt.endswith("s"):
            parts.append(f'.{name} = "{v}"')
        else:
            parts.append(f".{name} = {v}")
    return ", ".join(parts)


def c_image_value(values):
    parts = []
    for name, fmt, _ in IMAGE_INFO:
        v = values.get(name, 0)
        parts.append(f'.{name} = "{v}"' if fmt.endswith("s") else f".{name} = {v}u")
    return ", ".join(parts)


def main():
    c = ["/* Generated by protocol/vectors/generate.py: do not edit. */",
         '#include "cbx_vectors.h"', "", "const cbx_vector cbx_vectors[] = {"]
    md = ["# Protocol v1 golden vectors", "",
          "Generated by `protocol/vectors/generate.py` (an independent Python encoding of the",
          "layout in `protocol/README.md`); `cbx_vectors.c` holds the same bytes for the C tests.",
          "Offsets are from byte 0 (the report ID); the CRC is bytes 62..63.", ""]
    for name, kind, values, desc in GOOD:
        data = encode(kind, values)
        c.append(f"  {{\"{name}\", \"{kind}\", CBX_OK, 64, {{\n{c_bytes(data)}\n    }},")
        c.append(f"   .value.{kind} = {{{c_value(kind, values)}}}}},")
        md += [f"## {name}: {desc}", "", "```"]
        md += [f"{i:02d}: " + " ".join(f"{b:02X}" for b in data[i:i + 16]) for i in range(0, 64, 16)]
        md += ["```", ""]
        fields = HEADER + LAYOUTS[kind][2]
        md += ["| field | bytes | value |", "|---|---|---|"]
        md.append(f"| report id | 0 | 0x{LAYOUTS[kind][0]:02X} |")
        md.append("| version | 1 | 1 |")
        for fname, fmt, off in fields:
            size = struct.calcsize(fmt)
            v = values.get(fname, 0)
            shown = f'"{v}"' if fmt.endswith("s") else (f"{v} (0x{v & 0xFFFFFFFF:X})" if isinstance(v, int) and (v < 0 or v > 9) else str(v))
            md.append(f"| {fname} | {off}..{off + size - 1} | {shown} |")
        md.append(f"| crc | 62..63 | 0x{struct.unpack_from('<H', data, 62)[0]:04X} |")
        md.append("")
    for name, kind, data, status, desc in BAD:
        padded = data + bytes(64 - len(data))
        c.append(f"  {{\"{name}\", \"{kind}\", {status}, {len(data)}, {{\n{c_bytes(padded)}\n    }}, .value.state = {{.header = {{0, 0u, 0u}}}}}},")
        md += [f"## {name} → {status}: {desc}", "", "```"]
        md += [f"{i:02d}: " + " ".join(f"{b:02X}" for b in data[i:i + 16]) for i in range(0, len(data), 16)]
        md += ["```", ""]
    c += ["};", "", "const size_t cbx_vector_count = sizeof cbx_vectors / sizeof cbx_vectors[0];", ""]
    c += ["const cbx_image_info_vector cbx_image_info_vectors[] = {"]
    md += ["# Firmware image info block", "",
           "64 bytes at image offset 0x200 (`cbx_image_info_decode`); no report ID, version byte or CRC.", ""]
    for name, data, status, values, desc in IMAGE_VECTORS:
        value = f"{{{c_image_value(values)}}}" if values else "{0}"
        c.append(f"  {{\"{name}\", {status}, {{\n{c_bytes(data)}\n    }}, {value}}},")
        md += [f"## {name} → {status}: {desc}", "", "```"]
        md += [f"{i:02d}: " + " ".join(f"{b:02X}" for b in data[i:i + 16]) for i in range(0, 64, 16)]
        md += ["```", ""]
        if values:
            md += ["| field | bytes | value |", "|---|---|---|", "| magic | 0..3 | \"CBXI\" (0x49584243) |",
                   "| layout | 4 | 1 |", "| size | 5 | 64 |"]
            for fname, fmt, off in IMAGE_INFO:
                size = struct.calcsize(fmt)
                v = values.get(fname, 0)
                md.append(f"| {fname} | {off}..{off + size - 1} | " + (f'"{v}"' if fmt.endswith("s") else str(v)) + " |")
            md.append("")
    c += ["};", "",
          "const size_t cbx_image_info_vector_count = sizeof cbx_image_info_vectors / sizeof cbx_image_info_vectors[0];",
          ""]
    with open(os.path.join(HERE, "cbx_vectors.c"), "w") as f:
        f.write("\n".join(c))
    with open(os.path.join(HERE, "VECTORS.md"), "w") as f:
        f.write("\n".join(md))
    # Raw files for fuzz seed corpora.
    raw = os.path.join(HERE, "raw")
    os.makedirs(raw, exist_ok=True)
    for name, kind, values, _ in GOOD:
        open(os.path.join(raw, name + ".bin"), "wb").write(encode(kind, values))
    for name, _, data, _, _ in BAD:
        open(os.path.join(raw, name + ".bin"), "wb").write(data)
    for name, data, _, _, _ in IMAGE_VECTORS:
        open(os.path.join(raw, name + ".bin"), "wb").write(data)


if __name__ == "__main__":
    main()
