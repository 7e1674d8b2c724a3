/* USB OTG FS device driver (RM0383 chapter 22, slave mode): core set-up, FIFO allocation,
 * the interrupt handler (reset, enumeration done, receive FIFO, endpoint interrupts, SOF) and
 * the endpoint 0 control transfer stages. Written for this project. */
#include "usb_otgfs.h"

#include <string.h>

#include "board.h"
#include "protocol/cbx_bytes.h"
#include "stm32f411_regs.h"

/* FIFO RAM: 320 words. RX 128 words, EP0 TX 32 words, EP1 TX 32 words. */
#define RX_FIFO_WORDS 128u
#define TX0_FIFO_WORDS 32u
#define TX1_FIFO_WORDS 32u
#define OTG_PRIORITY 0x40u

typedef enum { EP0_IDLE, EP0_DATA_IN, EP0_DATA_OUT, EP0_STATUS } ep0_stage;

static struct {
  uint8_t setup_raw[8];
  uint8_t buffer[USB_EP0_BUFFER];
  uint16_t in_length, in_sent;
  bool in_zlp;
  uint16_t out_expected, out_received;
  ep0_stage stage;
} ep0;

static uint8_t ep1_out_buffer[USB_EP1_SIZE];
static uint16_t ep1_out_received;
static volatile bool ep1_in_pending;

/* The core's own operations (AHB idle, FIFO flush, soft reset) end within a few dozen AHB
 * cycles (RM0383 22.17.3). The waits are bounded all the same: a core that never answers must
 * not hang the USB interrupt forever while the control tick, which preempts it, keeps the
 * watchdog from resetting the chip. */
#define OTG_WAIT_LOOPS 100000u

static void wait_while(volatile uint32_t* reg, uint32_t mask, uint32_t value) {
  for (uint32_t i = 0; i < OTG_WAIT_LOOPS && (*reg & mask) == value; ++i) {
  }
}

static void wait_ahb_idle(void) { wait_while(&OTG_GRSTCTL, GRSTCTL_AHBIDL, 0u); }

static void flush_fifos(void) {
  wait_ahb_idle();
  OTG_GRSTCTL = GRSTCTL_TXFFLSH | GRSTCTL_TXFNUM_ALL;
  wait_while(&OTG_GRSTCTL, GRSTCTL_TXFFLSH, GRSTCTL_TXFFLSH);
  OTG_GRSTCTL = GRSTCTL_RXFFLSH;
  wait_while(&OTG_GRSTCTL, GRSTCTL_RXFFLSH, GRSTCTL_RXFFLSH);
}

void usb_otgfs_init(void) {
  RCC_AHB1ENR |= RCC_AHB1ENR_GPIOA;
  for (uint32_t pin = 11u; pin <= 12u; ++pin) {
    GPIOA->MODER = (GPIOA->MODER & ~(3u << (2u * pin))) | (GPIO_MODE_AF << (2u * pin));
    GPIOA->OSPEEDR |= 3u << (2u * pin);
    GPIOA->AFR[1] = (GPIOA->AFR[1] & ~(0xFu << (4u * (pin - 8u)))) | (10u << (4u * (pin - 8u)));
  }
  RCC_AHB2ENR |= RCC_AHB2ENR_OTGFS;
  (void)RCC_AHB2ENR;

  OTG_GAHBCFG = 0u;
  OTG_GUSBCFG |= GUSBCFG_PHYSEL;
  wait_ahb_idle();
  OTG_GRSTCTL = GRSTCTL_CSRST;
  wait_while(&OTG_GRSTCTL, GRSTCTL_CSRST, GRSTCTL_CSRST);
  wait_ahb_idle();
  board_delay_us(10u);

  /* Internal PHY on, no VBUS sensing (the board is bus- or self-powered, PA9 is free). */
  OTG_GCCFG = GCCFG_PWRDWN | GCCFG_NOVBUSSENS;
  OTG_GUSBCFG = (OTG_GUSBCFG & ~(GUSBCFG_TRDT_MASK | GUSBCFG_FHMOD)) | GUSBCFG_FDMOD |
                GUSBCFG_TRDT(6u) | GUSBCFG_PHYSEL;
  board_delay_us(25000u); /* forced device mode takes effect after 25 ms */

  OTG_DCTL |= DCTL_SDIS;
  OTG_PCGCCTL = 0u;
  OTG_DCFG = (OTG_DCFG & ~3u) | DCFG_DSPD_FS;

  OTG_GRXFSIZ = RX_FIFO_WORDS;
  OTG_DIEPTXF0 = (TX0_FIFO_WORDS << 16) | RX_FIFO_WORDS;
  OTG_DIEPTXF(1) = (TX1_FIFO_WORDS << 16) | (RX_FIFO_WORDS + TX0_FIFO_WORDS);
  flush_fifos();

  OTG_DIEPMSK = 0u;
  OTG_DOEPMSK = 0u;
  OTG_DAINTMSK = 0u;
  OTG_DAINT = 0xFFFFFFFFu;
  for (uint32_t ep = 0; ep < 4u; ++ep) {
    OTG_DIEPCTL(ep) = (OTG_DIEPCTL(ep) & EPCTL_EPENA) ? (EPCTL_EPDIS | EPCTL_SNAK) : 0u;
    OTG_DOEPCTL(ep) = (OTG_DOEPCTL(ep) & EPCTL_EPENA) ? (EPCTL_EPDIS | EPCTL_SNAK) : 0u;
    OTG_DIEPTSIZ(ep) = 0u;
    OTG_DOEPTSIZ(ep) = 0u;
    OTG_DIEPINT(ep) = 0xFFu;
    OTG_DOEPINT(ep) = 0xFFu;
  }

  OTG_GINTSTS = 0xFFFFFFFFu;
  OTG_GINTMSK = GINT_USBRST | GINT_ENUMDNE | GINT_RXFLVL | GINT_IEPINT | GINT_OEPINT |
                GINT_USBSUSP | GINT_WKUPINT | GINT_SOF;
  OTG_GAHBCFG = GAHBCFG_GINT;
  NVIC_IPR8(IRQ_OTG_FS) = OTG_PRIORITY;
  NVIC_ISER(IRQ_OTG_FS / 32u) = 1u << (IRQ_OTG_FS % 32u);
  OTG_DCTL &= ~DCTL_SDIS; /* connect: D+ pull-up on */
}

void usb_otgfs_detach(void) {
  NVIC_ICER(IRQ_OTG_FS / 32u) = 1u << (IRQ_OTG_FS % 32u);
  OTG_DCTL |= DCTL_SDIS;
}

/* ---- FIFO access ---- */

static void fifo_write(uint32_t ep, const uint8_t* data, uint16_t length) {
  for (uint16_t i = 0; i < length; i += 4u) {
    uint32_t w = 0u;
    for (uint16_t k = 0; k < 4u && i + k < length; ++k) w |= (uint32_t)data[i + k] << (8u * k);
    OTG_FIFO(ep) = w;
  }
}

static void fifo_read(uint8_t* data, uint16_t length, uint16_t capacity) {
  for (uint16_t i = 0; i < length; i += 4u) {
    const uint32_t w = OTG_FIFO(0);
    for (uint16_t k = 0; k < 4u && i + k < length; ++k)
      if (i + k < capacity) data[i + k] = (uint8_t)(w >> (8u * k));
  }
}

static void ep_in_start(uint32_t ep, const uint8_t* data, uint16_t length) {
  OTG_DIEPTSIZ(ep) = EPTSIZ_PKTCNT1 | length;
  OTG_DIEPCTL(ep) |= EPCTL_EPENA | EPCTL_CNAK;
  if (length) fifo_write(ep, data, length);
}

static void ep0_out_arm(void) {
  OTG_DOEPTSIZ(0) = DOEPTSIZ0_STUPCNT3 | EPTSIZ_PKTCNT1 | USB_EP0_SIZE;
  OTG_DOEPCTL(0) |= EPCTL_EPENA | EPCTL_CNAK;
}

static void ep1_out_arm(void) {
  ep1_out_received = 0u;
  OTG_DOEPTSIZ(1) = EPTSIZ_PKTCNT1 | USB_EP1_SIZE;
  OTG_DOEPCTL(1) |= EPCTL_EPENA | EPCTL_CNAK;
}

/* ---- Endpoint 0 ---- */

static void ep0_send_next(void) {
  const uint16_t left = (uint16_t)(ep0.in_length - ep0.in_sent);
  const uint16_t chunk = left > USB_EP0_SIZE ? USB_EP0_SIZE : left;
  ep_in_start(0u, ep0.buffer + ep0.in_sent, chunk);
  ep0.in_sent = (uint16_t)(ep0.in_sent + chunk);
}

void usb_ep0_send(const uint8_t* data, uint16_t length, uint16_t requested) {
  if (length > requested) length = requested;
  if (length > USB_EP0_BUFFER) length = USB_EP0_BUFFER;
  memcpy(ep0.buffer, data, length);
  ep0.in_length = length;
  ep0.in_sent = 0u;
  /* A short answer that is a multiple of the packet size ends with a zero-length packet. */
  ep0.in_zlp = length != 0u && length < requested && length % USB_EP0_SIZE == 0u; /* an empty answer is one ZLP */
  ep0.stage = EP0_DATA_IN;
  ep0_out_arm(); /* ready for the host's status OUT (or an early SETUP) */
  ep0_send_next();
}

void usb_ep0_receive(uint16_t length) {
  ep0.out_expected = length;
  ep0.out_received = 0u;
  ep0.stage = EP0_DATA_OUT;
  ep0_out_arm();
}

void usb_ep0_status(void) {
  ep0.stage = EP0_STATUS;
  ep_in_start(0u, 0, 0u);
  ep0_out_arm();
}

void usb_ep0_stall(void) {
  OTG_DIEPCTL(0) |= EPCTL_STALL;
  OTG_DOEPCTL(0) |= EPCTL_STALL;
  ep0.stage = EP0_IDLE;
  ep0_out_arm();
}

void usb_set_address(uint8_t address) {
  OTG_DCFG = (OTG_DCFG & ~DCFG_DAD_MASK) | DCFG_DAD(address);
}

/* ---- Endpoint 1 ---- */

void usb_ep1_configure(bool enable) {
  if (!enable) {
    OTG_DAINTMSK &= ~((1u << 1) | (1u << 17));
    if (OTG_DIEPCTL(1) & EPCTL_EPENA) OTG_DIEPCTL(1) |= EPCTL_EPDIS | EPCTL_SNAK;
    if (OTG_DOEPCTL(1) & EPCTL_EPENA) OTG_DOEPCTL(1) |= EPCTL_EPDIS | EPCTL_SNAK;
    OTG_DIEPCTL(1) &= ~EPCTL_USBAEP;
    OTG_DOEPCTL(1) &= ~EPCTL_USBAEP;
    ep1_in_pending = false;
    return;
  }
  OTG_DIEPCTL(1) = EPCTL_MPSIZ(USB_EP1_SIZE) | EPCTL_EPTYP_INTERRUPT | EPCTL_TXFNUM(1u) |
                   EPCTL_SD0PID | EPCTL_USBAEP | EPCTL_SNAK;
  OTG_DOEPCTL(1) = EPCTL_MPSIZ(USB_EP1_SIZE) | EPCTL_EPTYP_INTERRUPT | EPCTL_SD0PID | EPCTL_USBAEP;
  OTG_DAINTMSK |= (1u << 1) | (1u << 17);
  ep1_in_pending = false;
  ep1_out_arm();
}

bool usb_ep1_in_busy(void) { return ep1_in_pending; }

bool usb_ep1_in_send(const uint8_t* data, uint16_t length) {
  if (OTG_DTXFSTS(1) < (uint32_t)(length + 3u) / 4u) return false;
  ep1_in_pending = true;
  ep_in_start(1u, data, length);
  return true;
}

void usb_ep1_stall(bool in, bool stall) {
  volatile uint32_t* ctl = in ? &OTG_DIEPCTL(1) : &OTG_DOEPCTL(1);
  if (stall) {
    *ctl |= EPCTL_STALL;
  } else {
    *ctl = (*ctl & ~EPCTL_STALL) | EPCTL_SD0PID; /* clearing a halt resets the data toggle */
    if (!in) ep1_out_arm();
  }
}

bool usb_ep1_stalled(bool in) { return ((in ? OTG_DIEPCTL(1) : OTG_DOEPCTL(1)) & EPCTL_STALL) != 0u; }

/* ---- Interrupt handler ---- */

static void bus_reset(void) {
  flush_fifos();
  for (uint32_t ep = 0; ep < 4u; ++ep) {
    OTG_DIEPINT(ep) = 0xFFu;
    OTG_DOEPINT(ep) = 0xFFu;
    OTG_DOEPCTL(ep) |= EPCTL_SNAK;
  }
  OTG_DAINT = 0xFFFFFFFFu;
  OTG_DAINTMSK = (1u << 0) | (1u << 16);
  OTG_DOEPMSK = DOEPINT_STUP | EPINT_XFRC;
  OTG_DIEPMSK = EPINT_XFRC;
  usb_set_address(0u);
  usb_ep1_configure(false);
  ep0.stage = EP0_IDLE;
  ep0_out_arm();
  usb_device_reset();
}

static void receive_fifo(void) {
  const uint32_t status = OTG_GRXSTSP;
  const uint32_t ep = GRXSTS_EPNUM(status);
  const uint16_t count = (uint16_t)GRXSTS_BCNT(status);
  switch (GRXSTS_PKTSTS(status)) {
    case PKTSTS_SETUP_DATA:
      fifo_read(ep0.setup_raw, count, sizeof ep0.setup_raw);
      break;
    case PKTSTS_OUT_DATA:
      if (ep == 0u) {
        const uint16_t room = (uint16_t)(sizeof ep0.buffer - ep0.out_received);
        fifo_read(ep0.buffer + ep0.out_received, count, room);
        ep0.out_received = (uint16_t)(ep0.out_received + (count < room ? count : room));
      } else if (ep == 1u) {
        const uint16_t room = (uint16_t)(sizeof ep1_out_buffer - ep1_out_received);
        fifo_read(ep1_out_buffer + ep1_out_received, count, room);
        ep1_out_received = (uint16_t)(ep1_out_received + (count < room ? count : room));
      } else {
        fifo_read(0, count, 0u);
      }
      break;
    default: /* transfer / setup complete: nothing in the FIFO */
      break;
  }
}

static void setup_stage(void) {
  usb_setup s;
  s.bmRequestType = ep0.setup_raw[0];
  s.bRequest = ep0.setup_raw[1];
  s.wValue = cbx_get_u16(&ep0.setup_raw[2]);
  s.wIndex = cbx_get_u16(&ep0.setup_raw[4]);
  s.wLength = cbx_get_u16(&ep0.setup_raw[6]);
  ep0.stage = EP0_IDLE;
  if (!usb_device_setup(&s)) usb_ep0_stall();
}

static void out_endpoints(void) {
  const uint32_t daint = OTG_DAINT & OTG_DAINTMSK;
  if (daint & (1u << 16)) {
    const uint32_t flags = OTG_DOEPINT(0);
    OTG_DOEPINT(0) = flags;
    if ((flags & EPINT_XFRC) && ep0.stage == EP0_DATA_OUT) {
      if (ep0.out_received >= ep0.out_expected) {
        if (usb_device_ep0_out(ep0.buffer, ep0.out_expected)) usb_ep0_status();
        else usb_ep0_stall();
      } else {
        OTG_DOEPTSIZ(0) = DOEPTSIZ0_STUPCNT3 | EPTSIZ_PKTCNT1 | USB_EP0_SIZE;
        OTG_DOEPCTL(0) |= EPCTL_EPENA | EPCTL_CNAK;
      }
    } else if (flags & EPINT_XFRC) {
      ep0_out_arm(); /* status OUT of a control read done */
    }
    if (flags & DOEPINT_STUP) setup_stage();
  }
  if (daint & (1u << 17)) {
    const uint32_t flags = OTG_DOEPINT(1);
    OTG_DOEPINT(1) = flags;
    if (flags & EPINT_XFRC) {
      usb_device_ep1_out(ep1_out_buffer, ep1_out_received);
      ep1_out_arm();
    }
  }
}

static void in_endpoints(void) {
  const uint32_t daint = OTG_DAINT & OTG_DAINTMSK;
  if (daint & (1u << 0)) {
    const uint32_t flags = OTG_DIEPINT(0);
    OTG_DIEPINT(0) = flags;
    if ((flags & EPINT_XFRC) && ep0.stage == EP0_DATA_IN) {
      if (ep0.in_sent < ep0.in_length) {
        ep0_send_next();
      } else if (ep0.in_zlp) {
        ep0.in_zlp = false;
        ep_in_start(0u, 0, 0u);
      } else {
        ep0.stage = EP0_STATUS;
      }
    }
  }
  if (daint & (1u << 1)) {
    const uint32_t flags = OTG_DIEPINT(1);
    OTG_DIEPINT(1) = flags;
    if (flags & EPINT_XFRC) ep1_in_pending = false;
  }
}

void OTG_FS_IRQHandler(void);
void OTG_FS_IRQHandler(void) {
  const uint32_t status = OTG_GINTSTS & OTG_GINTMSK;
  if (status & GINT_USBRST) {
    OTG_GINTSTS = GINT_USBRST;
    bus_reset();
  }
  if (status & GINT_ENUMDNE) {
    OTG_GINTSTS = GINT_ENUMDNE;
    OTG_DIEPCTL(0) &= ~3u; /* MPSIZ 0 = 64 bytes */
    OTG_DCTL |= DCTL_CGINAK;
  }
  if (status & GINT_RXFLVL) {
    OTG_GINTMSK &= ~GINT_RXFLVL;
    while (OTG_GINTSTS & GINT_RXFLVL) receive_fifo();
    OTG_GINTMSK |= GINT_RXFLVL;
  }
  if (status & GINT_OEPINT) out_endpoints();
  if (status & GINT_IEPINT) in_endpoints();
  if (status & GINT_SOF) {
    OTG_GINTSTS = GINT_SOF;
    usb_device_sof();
  }
  if (status & (GINT_USBSUSP | GINT_WKUPINT)) {
    OTG_GINTSTS = status & (GINT_USBSUSP | GINT_WKUPINT);
    if ((status & GINT_USBSUSP) && !(status & GINT_WKUPINT)) usb_device_suspend();
  }
}
