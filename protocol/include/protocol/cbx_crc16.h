#ifndef CBX_CRC16_H
#define CBX_CRC16_H
/* CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR.
 * Check value: the ASCII bytes "123456789" give 0x29B1. */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

uint16_t cbx_crc16(const uint8_t* data, size_t length);
/* Continues a CRC over more bytes: cbx_crc16_update(cbx_crc16(a), b) == CRC of a then b. */
uint16_t cbx_crc16_update(uint16_t crc, const uint8_t* data, size_t length);

#ifdef __cplusplus
}
#endif
#endif
