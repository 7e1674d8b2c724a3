/* Force-included (-include) by the host build of the STM32F411 port sources in
 * test_usb_otgfs: the register blocks live in RAM arrays defined by the test, so the driver,
 * the USB glue and the port's HAL run unchanged on the host. Reads return what was last written
 * (no write-1-to-clear, no FIFOs): the test sets the status registers before each interrupt. */
#ifndef CBX_REGS_IN_RAM_H
#define CBX_REGS_IN_RAM_H
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif
extern uint32_t cbx_test_periph[0x24000u / 4u]; /* APB1, APB2, AHB1 */
extern uint32_t cbx_test_otg[0x3000u / 4u];     /* OTG FS registers and the FIFO windows of EP0, EP1 */
extern uint32_t cbx_test_scs[0x1000u / 4u];     /* SysTick, NVIC, SCB */
extern uint32_t cbx_test_sysmem[0x8000u / 4u];  /* system memory: the unique device ID */
#ifdef __cplusplus
}
#endif

#define CBX_PERIPH_BASE ((uintptr_t)cbx_test_periph)
#define CBX_OTG_BASE ((uintptr_t)cbx_test_otg)
#define CBX_SCS_BASE ((uintptr_t)cbx_test_scs)
#define CBX_SYSMEM_BASE ((uintptr_t)cbx_test_sysmem)
#endif
