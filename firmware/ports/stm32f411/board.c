/* The STM32F411 board: peripheral set-up and the port contract (firmware/cbx_hal.h).
 *
 *   PA15 / PB3  TIM2 CH1/CH2  insertion encoder A/B (32-bit counter, input filter)
 *   PB4  / PB5  TIM3 CH1/CH2  rotation encoder A/B (16-bit counter, extended by the core)
 *   PB6  / PB7  TIM4 CH1/CH2  insertion / rotation PWM, 20 kHz
 *   PB12 / PB13               insertion / rotation direction (H-bridge), high = negative
 *   PB14                      actuator driver enable, high = enabled
 *   PB0  / PB1  ADC1 IN8/IN9  insertion / rotation current sense
 *   PA4         ADC1 IN4      actuator supply sense (1:11 divider)
 *   PB8         EXTI8         E-stop loop (normally closed to GND, pull-up: high = pressed)
 *   PC13                      status LED (active low)
 *   PA11 / PA12               USB D- / D+
 *   TIM5                      free-running 1 MHz time base */
#include <string.h>

#include "board.h"
#include "cbx_build_id.h"
#include "firmware/cbx_hal.h"
#include "stm32f411_regs.h"

#define ENCODER_FILTER 6u   /* fDTS/4, N = 6: pulses shorter than 250 ns are ignored */
#define IWDG_PRESCALER_DIV4 0u
#define IWDG_RELOAD_50MS 400u /* 32 kHz LSI / 4 = 8 kHz -> 50 ms */

#define PIN_ESTOP 8u
#define PIN_DIR_INSERTION 12u
#define PIN_DIR_ROTATION 13u
#define PIN_ENABLE 14u
#define PIN_LED 13u

static volatile uint32_t adc_raw[3];  /* insertion current, rotation current, supply */
static volatile bool bootloader_requested;
static volatile bool estop_tripped;     /* the loop opened (EXTI) since the core last read it */

static void gpio_mode(cbx_gpio_regs* port, uint32_t pin, uint32_t mode, uint32_t pull, uint32_t af) {
  port->MODER = (port->MODER & ~(3u << (2u * pin))) | (mode << (2u * pin));
  port->PUPDR = (port->PUPDR & ~(3u << (2u * pin))) | (pull << (2u * pin));
  port->OSPEEDR |= 2u << (2u * pin); /* fast */
  if (mode == GPIO_MODE_AF) {
    volatile uint32_t* afr = &port->AFR[pin / 8u];
    const uint32_t shift = 4u * (pin % 8u);
    *afr = (*afr & ~(0xFu << shift)) | (af << shift);
  }
}

static void gpio_write(cbx_gpio_regs* port, uint32_t pin, bool high) {
  port->BSRR = high ? (1u << pin) : (1u << (pin + 16u));
}

static void encoder_timer_init(cbx_tim_regs* tim, uint32_t arr) {
  tim->CR1 = 0u;
  tim->SMCR = TIM_SMCR_SMS_ENCODER3;
  tim->CCMR1 = TIM_CCMR1_CC1S_TI1 | TIM_CCMR1_IC1F(ENCODER_FILTER) | TIM_CCMR1_CC2S_TI2 |
               TIM_CCMR1_IC2F(ENCODER_FILTER);
  tim->CCER = 0u; /* both inputs non-inverted, rising and falling edges counted by mode 3 */
  tim->ARR = arr;
  tim->CNT = 0u;
  tim->CR1 = TIM_CR1_CEN;
}

void board_outputs_off(void) {
  TIM4->CCR1 = 0u;
  TIM4->CCR2 = 0u;
  gpio_write(GPIOB, PIN_ENABLE, false);
}

void board_init(void) {
  RCC_AHB1ENR |= RCC_AHB1ENR_GPIOA | RCC_AHB1ENR_GPIOB | RCC_AHB1ENR_GPIOC;
  RCC_APB1ENR |= RCC_APB1ENR_TIM2 | RCC_APB1ENR_TIM3 | RCC_APB1ENR_TIM4 | RCC_APB1ENR_TIM5;
  RCC_APB2ENR |= RCC_APB2ENR_ADC1 | RCC_APB2ENR_SYSCFG;
  (void)RCC_APB2ENR;

  /* Outputs first, all off. */
  gpio_write(GPIOB, PIN_ENABLE, false);
  gpio_mode(GPIOB, PIN_ENABLE, GPIO_MODE_OUTPUT, GPIO_PULL_NONE, 0u);
  gpio_mode(GPIOB, PIN_DIR_INSERTION, GPIO_MODE_OUTPUT, GPIO_PULL_NONE, 0u);
  gpio_mode(GPIOB, PIN_DIR_ROTATION, GPIO_MODE_OUTPUT, GPIO_PULL_NONE, 0u);
  gpio_write(GPIOC, PIN_LED, true);
  gpio_mode(GPIOC, PIN_LED, GPIO_MODE_OUTPUT, GPIO_PULL_NONE, 0u);

  /* PWM: TIM4 CH1/CH2 at 20 kHz, preloaded compare. */
  gpio_mode(GPIOB, 6u, GPIO_MODE_AF, GPIO_PULL_NONE, 2u);
  gpio_mode(GPIOB, 7u, GPIO_MODE_AF, GPIO_PULL_NONE, 2u);
  TIM4->PSC = 0u;
  TIM4->ARR = CBX_PWM_PERIOD - 1u;
  TIM4->CCR1 = 0u;
  TIM4->CCR2 = 0u;
  TIM4->CCMR1 = TIM_CCMR1_OC1M_PWM1 | TIM_CCMR1_OC1PE | TIM_CCMR1_OC2M_PWM1 | TIM_CCMR1_OC2PE;
  TIM4->CCER = TIM_CCER_CC1E | TIM_CCER_CC2E;
  TIM4->EGR = TIM_EGR_UG;
  TIM4->CR1 = TIM_CR1_ARPE | TIM_CR1_CEN;

  /* Encoders: TIM2 (32-bit) on PA15/PB3 AF1, TIM3 (16-bit) on PB4/PB5 AF2, pull-ups for
   * open-collector encoders. */
  gpio_mode(GPIOA, 15u, GPIO_MODE_AF, GPIO_PULL_UP, 1u);
  gpio_mode(GPIOB, 3u, GPIO_MODE_AF, GPIO_PULL_UP, 1u);
  gpio_mode(GPIOB, 4u, GPIO_MODE_AF, GPIO_PULL_UP, 2u);
  gpio_mode(GPIOB, 5u, GPIO_MODE_AF, GPIO_PULL_UP, 2u);
  encoder_timer_init(TIM2, 0xFFFFFFFFu);
  encoder_timer_init(TIM3, 0xFFFFu);

  /* Time base: TIM5 at 1 MHz, 32-bit. */
  TIM5->PSC = CBX_TIMER_CLK_HZ / 1000000u - 1u;
  TIM5->ARR = 0xFFFFFFFFu;
  TIM5->EGR = TIM_EGR_UG;
  TIM5->CR1 = TIM_CR1_CEN;

  /* ADC: injected scan of IN8, IN9, IN4 (+IN4 again to use JSQ1..4 = JDR1..4 in order),
   * 24 MHz ADC clock, 56-cycle sampling: about 12 us per scan, one scan per control tick. */
  gpio_mode(GPIOB, 0u, GPIO_MODE_ANALOG, GPIO_PULL_NONE, 0u);
  gpio_mode(GPIOB, 1u, GPIO_MODE_ANALOG, GPIO_PULL_NONE, 0u);
  gpio_mode(GPIOA, 4u, GPIO_MODE_ANALOG, GPIO_PULL_NONE, 0u);
  ADC_CCR = ADC_CCR_ADCPRE_DIV4;
  ADC1_SMPR2 = (3u << (3u * 4u)) | (3u << (3u * 8u)) | (3u << (3u * 9u));
  ADC1_CR1 = ADC_CR1_SCAN;
  ADC1_JSQR = (3u << 20) | (8u << 0) | (9u << 5) | (4u << 10) | (4u << 15);
  ADC1_CR2 = ADC_CR2_ADON;
  board_delay_us(10u);
  ADC1_CR2 |= ADC_CR2_JSWSTART;

  /* E-stop: input with pull-up; a rising edge (loop opened) cuts the PWM in the interrupt,
   * before the next control tick sees it. */
  gpio_mode(GPIOB, PIN_ESTOP, GPIO_MODE_INPUT, GPIO_PULL_UP, 0u);
  SYSCFG_EXTICR(PIN_ESTOP / 4u) = (SYSCFG_EXTICR(PIN_ESTOP / 4u) & ~(0xFu << (4u * (PIN_ESTOP % 4u)))) |
                                  (1u << (4u * (PIN_ESTOP % 4u)));
  EXTI_RTSR |= 1u << PIN_ESTOP;
  EXTI_PR = 1u << PIN_ESTOP;
  EXTI_IMR |= 1u << PIN_ESTOP;
  NVIC_IPR8(IRQ_EXTI9_5) = 0x00u;
  NVIC_ISER(IRQ_EXTI9_5 / 32u) = 1u << (IRQ_EXTI9_5 % 32u);

  /* Independent watchdog, 50 ms, frozen while a debugger halts the core. */
  DBGMCU_APB1_FZ |= DBGMCU_IWDG_STOP;
  IWDG_KR = IWDG_KEY_START;
  IWDG_KR = IWDG_KEY_UNLOCK;
  IWDG_PR = IWDG_PRESCALER_DIV4;
  IWDG_RLR = IWDG_RELOAD_50MS;
  while (IWDG_SR != 0u) {
  }
  IWDG_KR = IWDG_KEY_RELOAD;
}

void board_delay_us(uint32_t us) {
  const uint32_t start = TIM5->CNT;
  while (TIM5->CNT - start < us) {
  }
}

void board_adc_cycle(void) {
  if (ADC1_SR & ADC_SR_JEOC) {
    adc_raw[0] = ADC1_JDR(1);
    adc_raw[1] = ADC1_JDR(2);
    adc_raw[2] = ADC1_JDR(3);
    ADC1_SR = ~ADC_SR_JEOC;
  }
  ADC1_CR2 |= ADC_CR2_JSWSTART;
}

void board_serial(char out[CBX_TEXT_FIELD + 1]) {
  static const char hex[] = "0123456789ABCDEF";
  const uint32_t w0 = CBX_REG(UID_BASE), w1 = CBX_REG(UID_BASE + 4u), w2 = CBX_REG(UID_BASE + 8u);
  const uint64_t id = ((uint64_t)(w0 ^ w2) << 16) ^ w1; /* 48 bits from the 96-bit ID */
  memcpy(out, "CBX-", 4);
  for (unsigned i = 0; i < 12u; ++i) out[4u + i] = hex[(id >> (44u - 4u * i)) & 0xFu];
  out[16] = '\0';
}

void board_core_config(cbx_core_config* config, bool hse_started) {
  memset(config, 0, sizeof *config);
  board_serial(config->serial);
  strcpy(config->board, CBX_BOARD_NAME);
  config->axis[CBX_AXIS_INSERTION] = (cbx_axis_config){CBX_ENCODER_COUNTER, 32u, CBX_BOARD_ACTUATOR,
                                                       CBX_BOARD_INSERTION_CPR};
  config->axis[CBX_AXIS_ROTATION] = (cbx_axis_config){CBX_ENCODER_COUNTER, 16u, CBX_BOARD_ACTUATOR,
                                                      CBX_BOARD_ROTATION_CPR};
  config->fw_version[0] = CBX_FW_MAJOR;
  config->fw_version[1] = CBX_FW_MINOR;
  config->fw_version[2] = CBX_FW_PATCH;
  strcpy(config->build, CBX_BUILD_ID);
  config->board_faults = hse_started ? 0u : CBX_BOARD_FAULT_HSE;
}

void EXTI9_5_IRQHandler(void);
void EXTI9_5_IRQHandler(void) {
  EXTI_PR = 1u << PIN_ESTOP;
  estop_tripped = true;
  board_outputs_off();
}

static bool estop_loop_open(void) { return (GPIOB->IDR >> PIN_ESTOP) & 1u; }

/* ---- The port contract ---- */

uint32_t cbx_hal_time_us(void) { return TIM5->CNT; }

uint32_t cbx_hal_encoder_counter(cbx_axis axis) {
  return axis == CBX_AXIS_INSERTION ? TIM2->CNT : TIM3->CNT;
}

int16_t cbx_hal_current_mA(cbx_axis axis) {
  const int32_t mv = (int32_t)(adc_raw[axis] * CBX_ADC_VREF_MV / 4095u);
  return (int16_t)((mv - CBX_CURRENT_ZERO_MV) * 1000 / CBX_CURRENT_MV_PER_A);
}

/* Also true once after the loop opened for less than a tick (a glitch, a loose wire): the
 * EXTI cut the PWM then, and the core latches the E-stop fault for it. Same priority as the
 * tick, so the EXTI cannot run between this read and the clear. */
bool cbx_hal_estop_pressed(void) {
  const bool tripped = estop_tripped;
  estop_tripped = false;
  return tripped || estop_loop_open();
}

void cbx_hal_actuator_set(cbx_axis axis, int16_t drive_permille) {
  if (bootloader_requested || estop_tripped || estop_loop_open()) {
    board_outputs_off();
    return;
  }
  int32_t d = drive_permille;
  if (d > 1000) d = 1000;
  if (d < -1000) d = -1000;
  const uint32_t duty = (uint32_t)(d < 0 ? -d : d) * CBX_PWM_PERIOD / 1000u;
  if (axis == CBX_AXIS_INSERTION) {
    gpio_write(GPIOB, PIN_DIR_INSERTION, d < 0);
    TIM4->CCR1 = duty;
  } else {
    gpio_write(GPIOB, PIN_DIR_ROTATION, d < 0);
    TIM4->CCR2 = duty;
  }
  gpio_write(GPIOB, PIN_ENABLE, true);
}

uint16_t cbx_hal_supply_mV(void) {
  return (uint16_t)(adc_raw[2] * CBX_ADC_VREF_MV / 4095u * CBX_SUPPLY_DIVIDER);
}

void cbx_hal_led_set(bool on) { gpio_write(GPIOC, PIN_LED, !on); }

void cbx_hal_watchdog_kick(void) { IWDG_KR = IWDG_KEY_RELOAD; }

void cbx_hal_bootloader_request(void) {
  bootloader_requested = true;
  board_outputs_off();
}

bool board_bootloader_requested(void) { return bootloader_requested; }
