#include "protocol/cbx_crc16.h"

uint16_t cbx_crc16_update(uint16_t crc, const uint8_t* data, size_t length) {
  for (size_t i = 0; i < length; ++i) {
    crc = (uint16_t)(crc ^ (uint16_t)((uint16_t)data[i] << 8));
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000u) ? (uint16_t)((uint16_t)(crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    }
  }
  return crc;
}

uint16_t cbx_crc16(const uint8_t* data, size_t length) {
  return cbx_crc16_update(0xFFFFu, data, length);
}
