# cmake -DQEMU=qemu-system-arm -DELF=prog.elf [-DICOUNT=6] [-DTIMEOUT=60] [-DEXPECT_TIMEOUT=ON]
#       -P RunQemu.cmake
# Runs one program on QEMU's mps2-an386 (Cortex-M4) with semihosting, so that its exit code is
# the program's, and fails when it has not finished within TIMEOUT seconds of wall time (default
# 60): a test body stuck in a loop fails the step (QEMU is killed) instead of hanging CI.
# EXPECT_TIMEOUT=ON turns the check around, for the check of the timeout itself.
if(NOT QEMU OR NOT ELF)
  message(FATAL_ERROR "RunQemu.cmake: QEMU and ELF are required")
endif()
if(NOT TIMEOUT)
  set(TIMEOUT 60)
endif()
set(args -M mps2-an386 -nographic -monitor none -serial none -semihosting-config enable=on,target=native)
if(DEFINED ICOUNT)
  list(APPEND args -icount shift=${ICOUNT})
endif()
get_filename_component(name ${ELF} NAME)
execute_process(COMMAND ${QEMU} ${args} -kernel ${ELF} TIMEOUT ${TIMEOUT} RESULT_VARIABLE rc)
set(timed_out OFF)
if(NOT rc MATCHES "^-?[0-9]+$")
  set(timed_out ON) # "Process terminated due to timeout"
endif()
if(EXPECT_TIMEOUT)
  if(NOT timed_out)
    message(FATAL_ERROR "qemu: ${name} was expected to hang and be stopped after ${TIMEOUT} s, but ended (${rc})")
  endif()
  message("qemu: ${name} hung as expected and was stopped after ${TIMEOUT} s")
  return()
endif()
if(timed_out)
  message(FATAL_ERROR "qemu: ${name} did not finish within ${TIMEOUT} s (a test body stuck in a loop?); stopped")
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "qemu: ${name} exited with ${rc}")
endif()
