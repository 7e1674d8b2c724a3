# The `cathbox-firmware` Debian package's files (component `firmware`, architecture all;
# scripts/package runs CPack): the STM32F411 image (.bin, from the stm32f411 preset's build,
# CATHBOX_FIRMWARE_BIN names another) and the DfuSe file `cathbox flash` writes to a box, packed
# from that image by `cathbox flash pack` when the package is made.
set(CATHBOX_FIRMWARE_BIN ${PROJECT_SOURCE_DIR}/build/stm32f411/bin/stm32f411_firmware.bin
    CACHE FILEPATH "the STM32F411 image the cathbox-firmware package carries")
set(_pkg ${PROJECT_SOURCE_DIR}/firmware/packaging)
set(_doc ${PROJECT_BINARY_DIR}/packaging/cathbox-firmware)
add_custom_command(OUTPUT ${_doc}/changelog.Debian.gz
  COMMAND ${CMAKE_COMMAND} -E make_directory ${_doc}
  COMMAND ${CMAKE_COMMAND} -E copy ${_pkg}/changelog.Debian ${_doc}/changelog.Debian
  COMMAND gzip -9nf ${_doc}/changelog.Debian
  DEPENDS ${_pkg}/changelog.Debian)
add_custom_target(cathbox_firmware_package_files ALL DEPENDS ${_doc}/changelog.Debian.gz)

set(_dest share/cathbox-firmware)
install(CODE "
  if(NOT EXISTS \"${CATHBOX_FIRMWARE_BIN}\")
    message(FATAL_ERROR \"cathbox-firmware: no image at ${CATHBOX_FIRMWARE_BIN}: build it first (scripts/build stm32f411)\")
  endif()
  set(_out \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${_dest}\")
  file(MAKE_DIRECTORY \"\${_out}\")
  execute_process(COMMAND \"$<TARGET_FILE:cathbox>\" flash pack \"${CATHBOX_FIRMWARE_BIN}\" \"\${_out}/stm32f411_firmware.dfu\"
                  RESULT_VARIABLE _rc OUTPUT_VARIABLE _said ERROR_VARIABLE _said)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR \"cathbox-firmware: cathbox flash pack ${CATHBOX_FIRMWARE_BIN}: \${_said}\")
  endif()" COMPONENT firmware)
install(FILES ${CATHBOX_FIRMWARE_BIN} DESTINATION ${_dest} COMPONENT firmware)
install(FILES ${_pkg}/copyright ${_doc}/changelog.Debian.gz DESTINATION share/doc/cathbox-firmware COMPONENT firmware)
