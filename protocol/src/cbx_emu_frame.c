#include "protocol/cbx_emu_frame.h"

#include <string.h>

#include "protocol/cbx_bytes.h"

/* Expected payload size of a frame kind after its header (and SETUP, for control requests);
 * returns -1 when any size up to CBX_EMU_CONTROL_DATA_MAX is allowed. */
static int cbx_emu_fixed_size(uint8_t kind) {
  switch (kind) {
    case CBX_EMU_HELLO: return (int)CBX_EMU_HELLO_SIZE;
    case CBX_EMU_IN:
    case CBX_EMU_OUT: return (int)CBX_REPORT_SIZE;
    default: return -1;
  }
}

static int cbx_emu_kind_known(uint8_t kind) {
  return kind >= CBX_EMU_HELLO && kind <= CBX_EMU_CONTROL_REPLY;
}

/* Data-stage size of a control request: wLength for host-to-device requests, none otherwise. */
static size_t cbx_emu_out_stage(const cbx_usb_setup* setup) {
  return (setup->request_type & 0x80u) != 0u ? 0u : setup->length;
}

int cbx_emu_frame_encode(const cbx_emu_frame* frame, uint8_t* out, size_t capacity) {
  if (frame == NULL || out == NULL || (frame->data == NULL && frame->data_length != 0u)) {
    return CBX_ERR_NULL;
  }
  if (!cbx_emu_kind_known(frame->kind) || frame->status > CBX_EMU_STATUS_STALL) return CBX_ERR_RANGE;
  const int fixed = cbx_emu_fixed_size(frame->kind);
  if (fixed >= 0 && frame->data_length != (size_t)fixed) return CBX_ERR_LENGTH;
  if (frame->data_length > CBX_EMU_CONTROL_DATA_MAX) return CBX_ERR_LENGTH;
  size_t offset = CBX_EMU_FRAME_HEADER;
  if (frame->kind == CBX_EMU_CONTROL) {
    if (frame->data_length != cbx_emu_out_stage(&frame->setup)) return CBX_ERR_LENGTH;
    offset += CBX_EMU_SETUP_SIZE;
  }
  if (capacity < offset + frame->data_length) return CBX_ERR_LENGTH;
  out[0] = frame->kind;
  out[1] = frame->status;
  cbx_put_u16(out + 2, frame->tag);
  if (frame->kind == CBX_EMU_CONTROL) {
    out[4] = frame->setup.request_type;
    out[5] = frame->setup.request;
    cbx_put_u16(out + 6, frame->setup.value);
    cbx_put_u16(out + 8, frame->setup.index);
    cbx_put_u16(out + 10, frame->setup.length);
  }
  if (frame->data_length != 0u) memcpy(out + offset, frame->data, frame->data_length);
  return (int)(offset + frame->data_length);
}

cbx_status cbx_emu_frame_decode(const uint8_t* in, size_t length, cbx_emu_frame* frame) {
  if (in == NULL || frame == NULL) return CBX_ERR_NULL;
  if (length < CBX_EMU_FRAME_HEADER || length > CBX_EMU_FRAME_MAX) return CBX_ERR_LENGTH;
  cbx_emu_frame f;
  memset(&f, 0, sizeof f);
  f.kind = in[0];
  f.status = in[1];
  f.tag = cbx_get_u16(in + 2);
  if (!cbx_emu_kind_known(f.kind) || f.status > CBX_EMU_STATUS_STALL) return CBX_ERR_RANGE;
  size_t offset = CBX_EMU_FRAME_HEADER;
  if (f.kind == CBX_EMU_CONTROL) {
    if (length < offset + CBX_EMU_SETUP_SIZE) return CBX_ERR_LENGTH;
    f.setup.request_type = in[4];
    f.setup.request = in[5];
    f.setup.value = cbx_get_u16(in + 6);
    f.setup.index = cbx_get_u16(in + 8);
    f.setup.length = cbx_get_u16(in + 10);
    offset += CBX_EMU_SETUP_SIZE;
    if (f.setup.length > CBX_EMU_CONTROL_DATA_MAX) return CBX_ERR_RANGE;
    if (length - offset != cbx_emu_out_stage(&f.setup)) return CBX_ERR_LENGTH;
  }
  const int fixed = cbx_emu_fixed_size(f.kind);
  if (fixed >= 0 && length - offset != (size_t)fixed) return CBX_ERR_LENGTH;
  if (length - offset > CBX_EMU_CONTROL_DATA_MAX) return CBX_ERR_LENGTH;
  f.data = in + offset;
  f.data_length = length - offset;
  if (f.data_length == 0u) f.data = NULL;
  *frame = f;
  return CBX_OK;
}

int cbx_emu_hello_encode(const cbx_emu_hello* hello, uint8_t* out, size_t capacity) {
  if (hello == NULL) return CBX_ERR_LENGTH;
  uint8_t body[CBX_EMU_HELLO_SIZE];
  cbx_put_u16(body, hello->vid);
  cbx_put_u16(body + 2, hello->pid);
  cbx_emu_frame frame;
  memset(&frame, 0, sizeof frame);
  frame.kind = CBX_EMU_HELLO;
  frame.data = body;
  frame.data_length = sizeof body;
  return cbx_emu_frame_encode(&frame, out, capacity);
}

cbx_status cbx_emu_hello_decode(const cbx_emu_frame* frame, cbx_emu_hello* hello) {
  if (frame == NULL || hello == NULL || frame->kind != CBX_EMU_HELLO) return CBX_ERR_RANGE;
  if (frame->data == NULL || frame->data_length != CBX_EMU_HELLO_SIZE) return CBX_ERR_LENGTH;
  hello->vid = cbx_get_u16(frame->data);
  hello->pid = cbx_get_u16(frame->data + 2);
  return CBX_OK;
}
