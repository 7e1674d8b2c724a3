/* The settings store of the port contract: a log of fixed 264-byte slots in flash sector 5
 * (128 KiB at 0x08020000, outside the image), 496 of them. A save programs the next blank
 * slot, the data words first and the header last (its magic word the very last), so an
 * interrupted save leaves no valid slot behind; load takes the newest valid slot.
 *
 * A save never erases while the host waits for the box: each 16 us word program runs from
 * RAM with interrupts masked for that word only, so the control tick and the USB interrupt
 * keep running between words (a save of the 136-byte block takes about 1 ms) and a control
 * request that arrives during it (`cathbox calibrate` reads the calibration back at once) is
 * answered in time (USB 2.0 9.2.6.4: the first data packet within 500 ms). Erasing the
 * sector stalls the CPU for 1-2 s (no fetch from a bank being erased), so it happens where no
 * host waits: at boot, before USB starts, when fewer than half the slots are blank
 * (flash_store_prepare: the newest block is written again at slot 0). A save that finds no
 * blank slot (more than 248 saves since power-on) erases there and then, as the last resort:
 * the box then answers no USB request for that erase. */
#include <string.h>

#include "board.h"
#include "firmware/cbx_hal.h"
#include "stm32f411_regs.h"

#define STORE_ADDR (CBX_FLASH_BASE + 0x20000u) /* sector 5 */
#define STORE_SECTOR 5u
#define STORE_SECTOR_BYTES 0x20000u
#define STORE_MAGIC 0xCB5E7701u
#define STORE_MAX 256u

typedef struct {
  uint32_t magic;
  uint32_t size;
} store_header;

#define SLOT_BYTES ((uint32_t)sizeof(store_header) + STORE_MAX)
#define SLOT_WORDS (SLOT_BYTES / 4u)
#define SLOT_COUNT (STORE_SECTOR_BYTES / SLOT_BYTES)

/* Runs from RAM with interrupts masked for this one word: flash is busy (no instruction fetch
 * from it) until BSY clears, about 16 us. */
__attribute__((section(".ramfunc"), noinline, long_call)) static uint32_t flash_program_word(uint32_t addr, uint32_t value) {
  uint32_t primask;
  __asm volatile("mrs %0, primask\n cpsid i" : "=r"(primask) : : "memory");
  FLASH_CR = FLASH_CR_PSIZE_X32 | FLASH_CR_PG;
  *(volatile uint32_t*)addr = value;
  while (FLASH_SR & FLASH_SR_BSY) IWDG_KR = IWDG_KEY_RELOAD;
  FLASH_CR = 0u;
  __asm volatile("msr primask, %0" : : "r"(primask) : "memory");
  return FLASH_SR & FLASH_SR_ERRORS;
}

/* Runs from RAM with interrupts masked through the 1-2 s erase (any fetch from flash would
 * stall until it ends), reloading the watchdog. */
__attribute__((section(".ramfunc"), noinline, long_call)) static uint32_t flash_erase_sector(uint32_t sector) {
  uint32_t primask;
  __asm volatile("mrs %0, primask\n cpsid i" : "=r"(primask) : : "memory");
  FLASH_CR = FLASH_CR_PSIZE_X32 | FLASH_CR_SER | FLASH_CR_SNB(sector);
  FLASH_CR |= FLASH_CR_STRT;
  while (FLASH_SR & FLASH_SR_BSY) IWDG_KR = IWDG_KEY_RELOAD;
  FLASH_CR = 0u;
  __asm volatile("msr primask, %0" : : "r"(primask) : "memory");
  return FLASH_SR & FLASH_SR_ERRORS;
}

static void flash_unlock(void) {
  if (FLASH_CR & FLASH_CR_LOCK) {
    FLASH_KEYR = FLASH_KEY1;
    FLASH_KEYR = FLASH_KEY2;
  }
  FLASH_SR = FLASH_SR_ERRORS; /* clear stale error flags */
}

static uint32_t slot_addr(uint32_t slot) { return STORE_ADDR + slot * SLOT_BYTES; }

static bool slot_blank(uint32_t slot) {
  const volatile uint32_t* w = (const volatile uint32_t*)slot_addr(slot);
  for (uint32_t i = 0; i < SLOT_WORDS; ++i) {
    if (w[i] != 0xFFFFFFFFu) return false;
  }
  return true;
}

static bool slot_valid(uint32_t slot) {
  const volatile store_header* h = (const volatile store_header*)slot_addr(slot);
  return h->magic == STORE_MAGIC && h->size <= STORE_MAX;
}

/* The newest valid slot (-1: none) and the first blank one (SLOT_COUNT: none). Saves take the
 * first blank slot, so every slot past it is blank too. */
typedef struct {
  int32_t newest;
  uint32_t next;
} store_scan;

static store_scan scan_store(void) {
  store_scan s = {-1, SLOT_COUNT};
  for (uint32_t slot = 0; slot < SLOT_COUNT; ++slot) {
    if (slot_blank(slot)) {
      s.next = slot;
      break;
    }
    if (slot_valid(slot)) s.newest = (int32_t)slot;
  }
  return s;
}

/* Programs `count` words of a slot image: the data, then the size, then the magic. */
static bool write_slot(uint32_t slot, const uint32_t* words, uint32_t count) {
  const uint32_t addr = slot_addr(slot);
  for (uint32_t i = 2; i < count; ++i) {
    if (flash_program_word(addr + 4u * i, words[i]) != 0u) return false;
  }
  return flash_program_word(addr + 4u, words[1]) == 0u && flash_program_word(addr, words[0]) == 0u;
}

static uint32_t slot_word_count(uint32_t size) { return (uint32_t)((sizeof(store_header) + size + 3u) / 4u); }

bool cbx_hal_store_load(void* data, size_t size) {
  const store_scan s = scan_store();
  if (s.newest < 0 || size > STORE_MAX) return false;
  const uint32_t addr = slot_addr((uint32_t)s.newest);
  if (((const store_header*)addr)->size != size) return false;
  memcpy(data, (const uint8_t*)addr + sizeof(store_header), size);
  return true;
}

bool cbx_hal_store_save(const void* data, size_t size) {
  if (size > STORE_MAX) return false;
  uint32_t words[SLOT_WORDS];
  memset(words, 0xFF, sizeof words);
  const store_header h = {STORE_MAGIC, (uint32_t)size};
  memcpy(words, &h, sizeof h);
  memcpy((uint8_t*)words + sizeof h, data, size);

  flash_unlock();
  store_scan s = scan_store();
  bool ok = true;
  if (s.next == SLOT_COUNT) { /* full: the last resort (see above) */
    ok = flash_erase_sector(STORE_SECTOR) == 0u;
    s.next = 0u;
  }
  if (ok) ok = write_slot(s.next, words, slot_word_count(size));
  FLASH_CR = FLASH_CR_LOCK;
  return ok;
}

void flash_store_prepare(void) {
  const store_scan s = scan_store();
  if (SLOT_COUNT - s.next >= SLOT_COUNT / 2u) return;
  uint32_t words[SLOT_WORDS];
  uint32_t count = 0u;
  if (s.newest >= 0) {
    memcpy(words, (const void*)slot_addr((uint32_t)s.newest), sizeof words);
    count = slot_word_count(words[1]);
  }
  flash_unlock();
  /* A power loss between the erase and the rewrite loses the block (the box then reports
   * not calibrated); it is at most once every 248 saves. */
  if (flash_erase_sector(STORE_SECTOR) == 0u && count != 0u) (void)write_slot(0u, words, count);
  FLASH_CR = FLASH_CR_LOCK;
}
