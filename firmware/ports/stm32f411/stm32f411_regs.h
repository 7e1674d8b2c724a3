#ifndef CBX_STM32F411_REGS_H
#define CBX_STM32F411_REGS_H
/* Register definitions for the STM32F411 peripherals the port uses, written for this project
 * from the reference manual (RM0383) and the Cortex-M4 generic user guide. Only what is used. */
#include <stdint.h>

/* Where the register blocks are. On the chip these are the RM0383 addresses. A build may place
 * them elsewhere to run the same port code against register blocks in RAM: the tick-cost
 * measurement on QEMU (firmware/qemu: -DCBX_PERIPH_BASE=... with constant addresses, so the
 * compiled instructions are those of the image) and the host tests of the OTG FS driver
 * (tests/firmware/ports/stm32f411). */
#ifndef CBX_PERIPH_BASE
#define CBX_PERIPH_BASE 0x40000000u /* APB1, APB2, AHB1: 0x40000000..0x40023FFF */
#endif
#ifndef CBX_OTG_BASE
#define CBX_OTG_BASE 0x50000000u    /* AHB2: USB OTG FS, registers and FIFO windows */
#endif
#ifndef CBX_SCS_BASE
#define CBX_SCS_BASE 0xE000E000u    /* Cortex-M4 system control space: SysTick, NVIC, SCB */
#endif
#ifndef CBX_FLASH_BASE
#define CBX_FLASH_BASE 0x08000000u  /* main flash (the settings store lives in sector 5) */
#endif
#ifndef CBX_SYSMEM_BASE
#define CBX_SYSMEM_BASE 0x1FFF0000u /* system memory: ROM bootloader, unique device ID */
#endif
#define CBX_PERIPH(offset) (CBX_PERIPH_BASE + (offset))

#define CBX_REG(addr) (*(volatile uint32_t*)(addr))

/* ---- Cortex-M4 core ---- */
#define SCB_VTOR CBX_REG(CBX_SCS_BASE + 0xD08u)
#define SCB_AIRCR CBX_REG(CBX_SCS_BASE + 0xD0Cu)
#define SCB_SHPR3 CBX_REG(CBX_SCS_BASE + 0xD20u)   /* bits 31:24 SysTick priority */
#define SCB_CPACR CBX_REG(CBX_SCS_BASE + 0xD88u)
#define SYST_CSR CBX_REG(CBX_SCS_BASE + 0x010u)
#define SYST_RVR CBX_REG(CBX_SCS_BASE + 0x014u)
#define SYST_CVR CBX_REG(CBX_SCS_BASE + 0x018u)
#define NVIC_ISER(n) CBX_REG(CBX_SCS_BASE + 0x100u + 4u * (n))
#define NVIC_ICER(n) CBX_REG(CBX_SCS_BASE + 0x180u + 4u * (n))
#define NVIC_ICPR(n) CBX_REG(CBX_SCS_BASE + 0x280u + 4u * (n))
#define NVIC_IPR8(irq) (*(volatile uint8_t*)(CBX_SCS_BASE + 0x400u + (irq)))
#define AIRCR_VECTKEY (0x05FAu << 16)
#define AIRCR_SYSRESETREQ (1u << 2)
#define DBGMCU_APB1_FZ CBX_REG(0xE0042008u)
#define DBGMCU_IWDG_STOP (1u << 12)

/* IRQ numbers used. */
#define IRQ_EXTI9_5 23u
#define IRQ_OTG_FS 67u
#define IRQ_COUNT 86u

/* ---- RCC ---- */
#define RCC_BASE CBX_PERIPH(0x23800u)
#define RCC_CR CBX_REG(RCC_BASE + 0x00u)
#define RCC_PLLCFGR CBX_REG(RCC_BASE + 0x04u)
#define RCC_CFGR CBX_REG(RCC_BASE + 0x08u)
#define RCC_AHB1ENR CBX_REG(RCC_BASE + 0x30u)
#define RCC_AHB2ENR CBX_REG(RCC_BASE + 0x34u)
#define RCC_APB1ENR CBX_REG(RCC_BASE + 0x40u)
#define RCC_APB2ENR CBX_REG(RCC_BASE + 0x44u)
#define RCC_CSR CBX_REG(RCC_BASE + 0x74u)
#define RCC_CR_HSION (1u << 0)
#define RCC_CR_HSEON (1u << 16)
#define RCC_CR_HSERDY (1u << 17)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)
#define RCC_PLLCFGR_SRC_HSE (1u << 22)
#define RCC_CFGR_SW_PLL 2u
#define RCC_CFGR_SWS_MASK (3u << 2)
#define RCC_CFGR_SWS_PLL (2u << 2)
#define RCC_CFGR_PPRE1_DIV2 (4u << 10)
#define RCC_AHB1ENR_GPIOA (1u << 0)
#define RCC_AHB1ENR_GPIOB (1u << 1)
#define RCC_AHB1ENR_GPIOC (1u << 2)
#define RCC_AHB2ENR_OTGFS (1u << 7)
#define RCC_APB1ENR_TIM2 (1u << 0)
#define RCC_APB1ENR_TIM3 (1u << 1)
#define RCC_APB1ENR_TIM4 (1u << 2)
#define RCC_APB1ENR_TIM5 (1u << 3)
#define RCC_APB1ENR_PWR (1u << 28)
#define RCC_APB2ENR_ADC1 (1u << 8)
#define RCC_APB2ENR_SYSCFG (1u << 14)

/* ---- PWR, FLASH ---- */
#define PWR_CR CBX_REG(CBX_PERIPH(0x7000u))
#define PWR_CR_VOS_SCALE1 (3u << 14)
#define FLASH_BASE_REG CBX_PERIPH(0x23C00u)
#define FLASH_ACR CBX_REG(FLASH_BASE_REG + 0x00u)
#define FLASH_KEYR CBX_REG(FLASH_BASE_REG + 0x04u)
#define FLASH_SR CBX_REG(FLASH_BASE_REG + 0x0Cu)
#define FLASH_CR CBX_REG(FLASH_BASE_REG + 0x10u)
#define FLASH_ACR_LATENCY_3WS 3u
#define FLASH_ACR_PRFTEN (1u << 8)
#define FLASH_ACR_ICEN (1u << 9)
#define FLASH_ACR_DCEN (1u << 10)
#define FLASH_KEY1 0x45670123u
#define FLASH_KEY2 0xCDEF89ABu
#define FLASH_SR_BSY (1u << 16)
#define FLASH_SR_ERRORS 0xF2u /* PGSERR, PGPERR, PGAERR, WRPERR, OPERR */
#define FLASH_CR_PG (1u << 0)
#define FLASH_CR_SER (1u << 1)
#define FLASH_CR_SNB(n) ((uint32_t)(n) << 3)
#define FLASH_CR_PSIZE_X32 (2u << 8)
#define FLASH_CR_STRT (1u << 16)
#define FLASH_CR_LOCK (1u << 31)

/* ---- GPIO ---- */
typedef struct {
  volatile uint32_t MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR, BSRR, LCKR, AFR[2];
} cbx_gpio_regs;
#define GPIOA ((cbx_gpio_regs*)CBX_PERIPH(0x20000u))
#define GPIOB ((cbx_gpio_regs*)CBX_PERIPH(0x20400u))
#define GPIOC ((cbx_gpio_regs*)CBX_PERIPH(0x20800u))
#define GPIO_MODE_INPUT 0u
#define GPIO_MODE_OUTPUT 1u
#define GPIO_MODE_AF 2u
#define GPIO_MODE_ANALOG 3u
#define GPIO_PULL_NONE 0u
#define GPIO_PULL_UP 1u

/* ---- General-purpose timers TIM2..TIM5 ---- */
typedef struct {
  volatile uint32_t CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR, RCR, CCR1,
      CCR2, CCR3, CCR4, BDTR, DCR, DMAR, OR;
} cbx_tim_regs;
#define TIM2 ((cbx_tim_regs*)CBX_PERIPH(0x0000u))
#define TIM3 ((cbx_tim_regs*)CBX_PERIPH(0x0400u))
#define TIM4 ((cbx_tim_regs*)CBX_PERIPH(0x0800u))
#define TIM5 ((cbx_tim_regs*)CBX_PERIPH(0x0C00u))
#define TIM_CR1_CEN (1u << 0)
#define TIM_CR1_ARPE (1u << 7)
#define TIM_SMCR_SMS_ENCODER3 3u          /* count on both edges of TI1 and TI2 (x4) */
#define TIM_CCMR1_CC1S_TI1 (1u << 0)
#define TIM_CCMR1_IC1F(f) ((uint32_t)(f) << 4)
#define TIM_CCMR1_CC2S_TI2 (1u << 8)
#define TIM_CCMR1_IC2F(f) ((uint32_t)(f) << 12)
#define TIM_CCMR1_OC1PE (1u << 3)
#define TIM_CCMR1_OC1M_PWM1 (6u << 4)
#define TIM_CCMR1_OC2PE (1u << 11)
#define TIM_CCMR1_OC2M_PWM1 (6u << 12)
#define TIM_CCER_CC1E (1u << 0)
#define TIM_CCER_CC2E (1u << 4)
#define TIM_EGR_UG (1u << 0)

/* ---- ADC1 ---- */
#define ADC1_BASE CBX_PERIPH(0x12000u)
#define ADC1_SR CBX_REG(ADC1_BASE + 0x00u)
#define ADC1_CR1 CBX_REG(ADC1_BASE + 0x04u)
#define ADC1_CR2 CBX_REG(ADC1_BASE + 0x08u)
#define ADC1_SMPR2 CBX_REG(ADC1_BASE + 0x10u)
#define ADC1_JSQR CBX_REG(ADC1_BASE + 0x38u)
#define ADC1_JDR(n) CBX_REG(ADC1_BASE + 0x3Cu + 4u * ((n) - 1u))
#define ADC_CCR CBX_REG(CBX_PERIPH(0x12304u))
#define ADC_SR_JEOC (1u << 2)
#define ADC_CR1_SCAN (1u << 8)
#define ADC_CR2_ADON (1u << 0)
#define ADC_CR2_JSWSTART (1u << 22)
#define ADC_CCR_ADCPRE_DIV4 (1u << 16)

/* ---- IWDG, EXTI, SYSCFG ---- */
#define IWDG_KR CBX_REG(CBX_PERIPH(0x3000u))
#define IWDG_PR CBX_REG(CBX_PERIPH(0x3004u))
#define IWDG_RLR CBX_REG(CBX_PERIPH(0x3008u))
#define IWDG_SR CBX_REG(CBX_PERIPH(0x300Cu))
#define IWDG_KEY_RELOAD 0xAAAAu
#define IWDG_KEY_UNLOCK 0x5555u
#define IWDG_KEY_START 0xCCCCu
#define EXTI_IMR CBX_REG(CBX_PERIPH(0x13C00u))
#define EXTI_RTSR CBX_REG(CBX_PERIPH(0x13C08u))
#define EXTI_FTSR CBX_REG(CBX_PERIPH(0x13C0Cu))
#define EXTI_PR CBX_REG(CBX_PERIPH(0x13C14u))
#define SYSCFG_MEMRMP CBX_REG(CBX_PERIPH(0x13800u))
#define SYSCFG_EXTICR(n) CBX_REG(CBX_PERIPH(0x13808u) + 4u * (n)) /* n = 0..3, 4 lines each */
#define SYSCFG_MEMRMP_SYSTEM 1u

/* ---- Unique device ID, system memory (ROM bootloader) ---- */
#define UID_BASE (CBX_SYSMEM_BASE + 0x7A10u)
#define SYSTEM_MEMORY_BASE CBX_SYSMEM_BASE

/* ---- USB OTG full speed (device mode) ---- */
#define OTG_BASE CBX_OTG_BASE
#define OTG_REG(off) CBX_REG(OTG_BASE + (off))
#define OTG_GOTGCTL OTG_REG(0x000u)
#define OTG_GAHBCFG OTG_REG(0x008u)
#define OTG_GUSBCFG OTG_REG(0x00Cu)
#define OTG_GRSTCTL OTG_REG(0x010u)
#define OTG_GINTSTS OTG_REG(0x014u)
#define OTG_GINTMSK OTG_REG(0x018u)
#define OTG_GRXSTSP OTG_REG(0x020u)
#define OTG_GRXFSIZ OTG_REG(0x024u)
#define OTG_DIEPTXF0 OTG_REG(0x028u)
#define OTG_GCCFG OTG_REG(0x038u)
#define OTG_DIEPTXF(n) OTG_REG(0x104u + 4u * ((n) - 1u))
#define OTG_DCFG OTG_REG(0x800u)
#define OTG_DCTL OTG_REG(0x804u)
#define OTG_DSTS OTG_REG(0x808u)
#define OTG_DIEPMSK OTG_REG(0x810u)
#define OTG_DOEPMSK OTG_REG(0x814u)
#define OTG_DAINT OTG_REG(0x818u)
#define OTG_DAINTMSK OTG_REG(0x81Cu)
#define OTG_DIEPCTL(n) OTG_REG(0x900u + 0x20u * (n))
#define OTG_DIEPINT(n) OTG_REG(0x908u + 0x20u * (n))
#define OTG_DIEPTSIZ(n) OTG_REG(0x910u + 0x20u * (n))
#define OTG_DTXFSTS(n) OTG_REG(0x918u + 0x20u * (n))
#define OTG_DOEPCTL(n) OTG_REG(0xB00u + 0x20u * (n))
#define OTG_DOEPINT(n) OTG_REG(0xB08u + 0x20u * (n))
#define OTG_DOEPTSIZ(n) OTG_REG(0xB10u + 0x20u * (n))
#define OTG_PCGCCTL OTG_REG(0xE00u)
#define OTG_FIFO(n) OTG_REG(0x1000u + 0x1000u * (n))

#define GAHBCFG_GINT (1u << 0)
#define GUSBCFG_PHYSEL (1u << 6)
#define GUSBCFG_TRDT(n) ((uint32_t)(n) << 10)
#define GUSBCFG_TRDT_MASK (0xFu << 10)
#define GUSBCFG_FHMOD (1u << 29)
#define GUSBCFG_FDMOD (1u << 30)
#define GRSTCTL_CSRST (1u << 0)
#define GRSTCTL_RXFFLSH (1u << 4)
#define GRSTCTL_TXFFLSH (1u << 5)
#define GRSTCTL_TXFNUM_ALL (0x10u << 6)
#define GRSTCTL_AHBIDL (1u << 31)
#define GINT_SOF (1u << 3)
#define GINT_RXFLVL (1u << 4)
#define GINT_USBSUSP (1u << 11)
#define GINT_USBRST (1u << 12)
#define GINT_ENUMDNE (1u << 13)
#define GINT_IEPINT (1u << 18)
#define GINT_OEPINT (1u << 19)
#define GINT_WKUPINT (1u << 31)
#define GCCFG_PWRDWN (1u << 16)
#define GCCFG_NOVBUSSENS (1u << 21)
#define DCFG_DSPD_FS 3u
#define DCFG_DAD_MASK (0x7Fu << 4)
#define DCFG_DAD(a) ((uint32_t)(a) << 4)
#define DCTL_SDIS (1u << 1)
#define DCTL_CGINAK (1u << 8)
#define EPCTL_MPSIZ(n) ((uint32_t)(n))
#define EPCTL_USBAEP (1u << 15)
#define EPCTL_EPTYP_INTERRUPT (3u << 18)
#define EPCTL_STALL (1u << 21)
#define EPCTL_TXFNUM(n) ((uint32_t)(n) << 22)
#define EPCTL_CNAK (1u << 26)
#define EPCTL_SNAK (1u << 27)
#define EPCTL_SD0PID (1u << 28)
#define EPCTL_EPDIS (1u << 30)
#define EPCTL_EPENA (1u << 31)
#define EPINT_XFRC (1u << 0)
#define DOEPINT_STUP (1u << 3)
#define EPTSIZ_PKTCNT1 (1u << 19)
#define DOEPTSIZ0_STUPCNT3 (3u << 29)
#define GRXSTS_EPNUM(s) ((s) & 0xFu)
#define GRXSTS_BCNT(s) (((s) >> 4) & 0x7FFu)
#define GRXSTS_PKTSTS(s) (((s) >> 17) & 0xFu)
#define PKTSTS_OUT_DATA 2u
#define PKTSTS_SETUP_DATA 6u

#endif
