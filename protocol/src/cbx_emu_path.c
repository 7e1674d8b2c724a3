#include <stdio.h>
#include <stdlib.h>

#include "protocol/cbx_emu_frame.h"

cbx_status cbx_emu_default_socket_path(char* out, size_t capacity) {
  if (out == NULL || capacity == 0u) return CBX_ERR_NULL;
  const char* explicit_path = getenv("CATHBOX_EMU_SOCKET");
  const char* runtime_dir = getenv("XDG_RUNTIME_DIR");
  int n;
  if (explicit_path != NULL && explicit_path[0] != '\0') {
    n = snprintf(out, capacity, "%s", explicit_path);
  } else if (runtime_dir != NULL && runtime_dir[0] != '\0') {
    n = snprintf(out, capacity, "%s/cathbox-emu.sock", runtime_dir);
  } else {
    n = snprintf(out, capacity, "/tmp/cathbox-emu.sock");
  }
  if (n < 0 || (size_t)n >= capacity) {
    out[0] = '\0';
    return CBX_ERR_LENGTH;
  }
  return CBX_OK;
}
