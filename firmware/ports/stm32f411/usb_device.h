#ifndef CBX_USB_DEVICE_H
#define CBX_USB_DEVICE_H
/* The Cathbox USB device (HID, protocol v1) on top of the OTG FS driver. */
#include "firmware/cbx_core.h"

/* Starts USB with `core` answering the reports; returns at once (interrupt driven). */
void usb_device_start(cbx_core* core);
/* What usb_device_start does before it starts the driver: `core` answers the reports. For the
 * tests that run the driver on register blocks in RAM (they never initialise the hardware). */
void usb_device_bind(cbx_core* core);

#endif
