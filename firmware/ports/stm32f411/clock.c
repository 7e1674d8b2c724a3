/* Clock tree: 25 MHz HSE / M 25 * N 192 = 192 MHz VCO; / P 2 = 96 MHz SYSCLK, / Q 4 = 48 MHz
 * for USB. AHB 96 MHz, APB1 48 MHz (timers 96 MHz), APB2 96 MHz. Flash: 3 wait states at
 * 96 MHz and 2.7..3.6 V, prefetch and caches on. Voltage scale 1 (needed above 84 MHz). */
#include "board.h"
#include "stm32f411_regs.h"

#define PLL_M_HSE 25u
#define PLL_M_HSI 16u
#define PLL_N 192u
#define PLL_P_DIV2 0u
#define PLL_Q 4u
#define HSE_STARTUP_LOOPS 500000u
#define PLLCFGR_FIELDS 0x0F437FFFu /* PLLM, PLLN, PLLP, PLLSRC, PLLQ */

bool board_clock_init(void) {
  RCC_APB1ENR |= RCC_APB1ENR_PWR;
  (void)RCC_APB1ENR; /* the PWR clock runs before its first access (as after every enable here) */
  PWR_CR = (PWR_CR & ~(3u << 14)) | PWR_CR_VOS_SCALE1;

  RCC_CR |= RCC_CR_HSEON;
  bool hse = false;
  for (uint32_t i = 0; i < HSE_STARTUP_LOOPS; ++i) {
    if (RCC_CR & RCC_CR_HSERDY) {
      hse = true;
      break;
    }
  }
  const uint32_t m = hse ? PLL_M_HSE : PLL_M_HSI;
  RCC_PLLCFGR = (RCC_PLLCFGR & ~PLLCFGR_FIELDS) | m | (PLL_N << 6) | (PLL_P_DIV2 << 16) |
                (hse ? RCC_PLLCFGR_SRC_HSE : 0u) | (PLL_Q << 24); /* reserved bits kept */

  FLASH_ACR = FLASH_ACR_LATENCY_3WS | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN | FLASH_ACR_DCEN;
  while ((FLASH_ACR & 0xFu) != FLASH_ACR_LATENCY_3WS) {
  }
  RCC_CFGR = RCC_CFGR_PPRE1_DIV2; /* AHB /1, APB1 /2, APB2 /1, still on HSI */

  RCC_CR |= RCC_CR_PLLON;
  while (!(RCC_CR & RCC_CR_PLLRDY)) {
  }
  RCC_CFGR = (RCC_CFGR & ~3u) | RCC_CFGR_SW_PLL;
  while ((RCC_CFGR & RCC_CFGR_SWS_MASK) != RCC_CFGR_SWS_PLL) {
  }
  if (!hse) RCC_CR &= ~RCC_CR_HSEON;
  return hse;
}
