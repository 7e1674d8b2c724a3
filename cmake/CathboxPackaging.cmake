# Debian packages with CPack (scripts/package), one component each: cathbox-server (`server`,
# host/server/packaging/package.cmake), cathbox (`app`, host/app/packaging/package.cmake) and
# cathbox-firmware (`firmware`, firmware/packaging/package.cmake; it needs the stm32f411 image).
# `cpack -D CPACK_COMPONENTS_ALL=app` makes one of them (tests/packaging).
set(CPACK_COMPONENTS_ALL server)
if(TARGET cathbox-trainer AND TARGET cathbox-box-bridge)
  include(${PROJECT_SOURCE_DIR}/host/app/packaging/package.cmake)
  list(APPEND CPACK_COMPONENTS_ALL app)
endif()
if(TARGET cathbox)
  include(${PROJECT_SOURCE_DIR}/firmware/packaging/package.cmake)
  list(APPEND CPACK_COMPONENTS_ALL firmware)
endif()
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "Cathbox maintainers <maintainers@users.noreply.h-seed-be078ec5.example>")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_SERVER_PACKAGE_NAME cathbox-server)
set(CPACK_DEBIAN_SERVER_PACKAGE_DEPENDS "adduser, init-system-helpers (>= 1.50)")
set(CPACK_DEBIAN_SERVER_PACKAGE_SUGGESTS "postgresql, postgresql-client")
set(CPACK_DEBIAN_SERVER_PACKAGE_CONTROL_EXTRA
    "${PROJECT_SOURCE_DIR}/host/server/packaging/postinst;${PROJECT_SOURCE_DIR}/host/server/packaging/prerm;${PROJECT_SOURCE_DIR}/host/server/packaging/postrm;${PROJECT_SOURCE_DIR}/host/server/packaging/conffiles")
set(CPACK_DEBIAN_SERVER_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_COMPONENT_SERVER_DESCRIPTION "Cathbox training centre server
cathbox-server joins Cathbox training rigs and instructors: a case library,
assignments with pass criteria, results checked by replaying session records,
and live sessions streamed to instructors, over HTTPS on SQLite or PostgreSQL.
Runs as the systemd service cathbox-server.")
set(CPACK_DEBIAN_APP_PACKAGE_NAME cathbox)
set(CPACK_DEBIAN_APP_PACKAGE_SECTION science)
set(CPACK_COMPONENT_APP_DESCRIPTION "haptic catheter-box training simulator: trainer, tools, emulated box
cathbox-trainer is the trainee's application: endovascular cases with wires
and catheters, driven by the Cathbox haptic box, an emulated box or a scripted
hand, with records that replay exactly; it can join a cathbox-server training
centre over HTTPS. The package also holds the cathbox tool (box information,
calibration, firmware updates, records), the emulated box cathbox-emu and its
WebSocket bridge, the bundled cases, and a udev rule that lets the user at the
seat and the plugdev group open the box and its DFU bootloader.")
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_NAME cathbox-firmware)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_SHLIBDEPS OFF)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_SUGGESTS cathbox)
set(CPACK_COMPONENT_FIRMWARE_DESCRIPTION "Cathbox box firmware (STM32F411)
The firmware of the Cathbox haptic box, for its STM32F411 board: the raw image
and the checked DfuSe file that 'cathbox flash' writes to a box through the
chip's ROM bootloader, in /usr/share/cathbox-firmware.")
include(CPack)
