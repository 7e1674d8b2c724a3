# Helpers for the cross-built firmware images.
find_program(CATHBOX_QEMU_ARM qemu-system-arm)

# cathbox_firmware_image(<target> FLASH_KIB n RAM_KIB n): after linking <target>.elf, writes
# .bin and .hex, prints flash and RAM use, and fails the build past the budget.
function(cathbox_firmware_image target)
  cmake_parse_arguments(A "" "FLASH_KIB;RAM_KIB" "" ${ARGN})
  set_target_properties(${target} PROPERTIES SUFFIX ".elf")
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_OBJCOPY} -O binary $<TARGET_FILE:${target}> $<TARGET_FILE_DIR:${target}>/${target}.bin
    COMMAND ${CMAKE_OBJCOPY} -O ihex $<TARGET_FILE:${target}> $<TARGET_FILE_DIR:${target}>/${target}.hex
    COMMAND ${CMAKE_COMMAND} -DOBJDUMP=${CMAKE_OBJDUMP} -DELF=$<TARGET_FILE:${target}>
            -DFLASH_KIB=${A_FLASH_KIB} -DRAM_KIB=${A_RAM_KIB}
            -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/CheckBudget.cmake
    VERBATIM)
endfunction()
