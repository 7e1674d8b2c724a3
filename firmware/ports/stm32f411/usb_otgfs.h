#ifndef CBX_USB_OTGFS_H
#define CBX_USB_OTGFS_H
/* The USB OTG FS peripheral in device mode (slave mode, no DMA): endpoint 0 control transfers
 * and endpoint 1 interrupt IN/OUT, 64-byte packets. The request handling above it is in
 * usb_device.c. */
#include <stdbool.h>
#include <stdint.h>

#define USB_EP0_SIZE 64u
#define USB_EP1_SIZE 64u
#define USB_EP0_BUFFER 160u

typedef struct {
  uint8_t bmRequestType;
  uint8_t bRequest;
  uint16_t wValue;
  uint16_t wIndex;
  uint16_t wLength;
} usb_setup;

/* Driver: set-up, connect (D+ pull-up) and detach. */
void usb_otgfs_init(void);
void usb_otgfs_detach(void);

/* Control endpoint, for the request handler. */
void usb_ep0_send(const uint8_t* data, uint16_t length, uint16_t requested); /* IN data stage */
void usb_ep0_receive(uint16_t length);   /* expect an OUT data stage of `length` bytes */
void usb_ep0_status(void);               /* zero-length IN status stage */
void usb_ep0_stall(void);
void usb_set_address(uint8_t address);

/* Endpoint 1 (interrupt IN 0x81 and OUT 0x01). */
void usb_ep1_configure(bool enable);
bool usb_ep1_in_busy(void);
bool usb_ep1_in_send(const uint8_t* data, uint16_t length); /* false: no room in its TX FIFO, not sent */
void usb_ep1_stall(bool in, bool stall);
bool usb_ep1_stalled(bool in);

/* Implemented by usb_device.c, called from the USB interrupt. */
void usb_device_reset(void);                            /* bus reset */
void usb_device_suspend(void);                          /* the bus went idle (suspend) */
bool usb_device_setup(const usb_setup* setup);          /* false: stall */
bool usb_device_ep0_out(const uint8_t* data, uint16_t length); /* data stage done; false: stall */
void usb_device_ep1_out(const uint8_t* data, uint16_t length);
void usb_device_sof(void);

#endif
