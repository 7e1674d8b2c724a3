/* A test body stuck in a loop: firmware_check runs it with a short timeout to show that the
 * QEMU runner (firmware/cmake/RunQemu.cmake) stops a program that never ends. */
int main(void);

int main(void) {
  for (volatile unsigned spins = 0;; spins = spins + 1u) {
  }
}
