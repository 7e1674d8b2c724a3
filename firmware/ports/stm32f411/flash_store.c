/* The settings store of the port contract: one block in flash sector 5 (128 KiB at
 * 0x08020000, outside the image). Erasing a 128 KiB sector takes about 1-2 s; the core only
 * saves from the main loop while the outputs are off, and the wait runs from RAM with
 * interrupts masked, reloading the watchdog. */
#include <string.h>

#include "firmware/cbx_hal.h"
#include "stm32f411_regs.h"

#define STORE_ADDR (CBX_FLASH_BASE + 0x20000u) /* sector 5 */
#define STORE_SECTOR 5u
#define STORE_MAGIC 0xCB5E7701u
#define STORE_MAX 256u

typedef struct {
  uint32_t magic;
  uint32_t size;
} store_header;

/* Runs from RAM: flash is busy (no instruction fetch from it) until BSY clears. */
__attribute__((section(".ramfunc"), noinline, long_call)) static uint32_t flash_wait(void) {
  while (FLASH_SR & FLASH_SR_BSY) IWDG_KR = IWDG_KEY_RELOAD;
  return FLASH_SR & FLASH_SR_ERRORS;
}

__attribute__((section(".ramfunc"), noinline, long_call)) static uint32_t flash_erase_sector(uint32_t sector) {
  FLASH_CR = FLASH_CR_PSIZE_X32 | FLASH_CR_SER | FLASH_CR_SNB(sector);
  FLASH_CR |= FLASH_CR_STRT;
  while (FLASH_SR & FLASH_SR_BSY) IWDG_KR = IWDG_KEY_RELOAD;
  FLASH_CR = 0u;
  return FLASH_SR & FLASH_SR_ERRORS;
}

static bool program_words(uint32_t addr, const uint32_t* words, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i) {
    FLASH_CR = FLASH_CR_PSIZE_X32 | FLASH_CR_PG;
    *(volatile uint32_t*)(addr + 4u * i) = words[i];
    if (flash_wait() != 0u) return false;
  }
  FLASH_CR = 0u;
  return true;
}

bool cbx_hal_store_load(void* data, size_t size) {
  const store_header* h = (const store_header*)STORE_ADDR;
  if (h->magic != STORE_MAGIC || h->size != size || size > STORE_MAX) return false;
  memcpy(data, (const uint8_t*)STORE_ADDR + sizeof *h, size);
  return true;
}

bool cbx_hal_store_save(const void* data, size_t size) {
  if (size > STORE_MAX) return false;
  uint32_t words[(sizeof(store_header) + STORE_MAX) / 4u];
  memset(words, 0xFF, sizeof words);
  const store_header h = {STORE_MAGIC, (uint32_t)size};
  memcpy(words, &h, sizeof h);
  memcpy((uint8_t*)words + sizeof h, data, size);
  const uint32_t count = (uint32_t)((sizeof h + size + 3u) / 4u);

  uint32_t primask;
  __asm volatile("mrs %0, primask\n cpsid i" : "=r"(primask) : : "memory");
  if (FLASH_CR & FLASH_CR_LOCK) {
    FLASH_KEYR = FLASH_KEY1;
    FLASH_KEYR = FLASH_KEY2;
  }
  FLASH_SR = FLASH_SR_ERRORS; /* clear stale error flags */
  bool ok = flash_erase_sector(STORE_SECTOR) == 0u;
  /* The header goes last, so an interrupted save leaves no valid block behind. */
  if (ok) ok = program_words(STORE_ADDR + 8u, words + 2, count - 2u);
  if (ok) ok = program_words(STORE_ADDR, words, 2u);
  FLASH_CR = FLASH_CR_LOCK;
  __asm volatile("msr primask, %0" : : "r"(primask) : "memory");
  return ok;
}
