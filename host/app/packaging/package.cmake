# The `cathbox` Debian package's files (component `app`; scripts/package runs CPack): the trainer,
# the `cathbox` tool, the emulated box and its browser bridge, the bundled cases, the udev rule for
# the box, a desktop entry for the trainer, a manual page per program made from its --help, the docs.
set(_pkg ${PROJECT_SOURCE_DIR}/host/app/packaging)
set(_man ${PROJECT_BINARY_DIR}/packaging/cathbox)
set(_programs cathbox-trainer cathbox cathbox-emu cathbox-box-bridge)
set(_summary_cathbox-trainer "the Cathbox trainer, the trainee's application")
set(_summary_cathbox "the Cathbox hardware engineer's and developer's tool")
set(_summary_cathbox-emu "the emulated Cathbox box")
set(_summary_cathbox-box-bridge "the emulated Cathbox box on a WebSocket, for the browser")
set(_pages)
foreach(_program IN LISTS _programs)
  add_custom_command(OUTPUT ${_man}/${_program}.1.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${_man}
    COMMAND ${CMAKE_COMMAND} -DPROGRAM=$<TARGET_FILE:${_program}> -DNAME=${_program} -DSECTION=1
            "-DSUMMARY=${_summary_${_program}}" -DOUT=${_man}/${_program}.1 -P ${PROJECT_SOURCE_DIR}/cmake/help_to_man.cmake
    COMMAND gzip -9nf ${_man}/${_program}.1
    DEPENDS ${_program} ${PROJECT_SOURCE_DIR}/cmake/help_to_man.cmake VERBATIM)
  list(APPEND _pages ${_man}/${_program}.1.gz)
endforeach()
add_custom_command(OUTPUT ${_man}/changelog.Debian.gz
  COMMAND ${CMAKE_COMMAND} -E make_directory ${_man}
  COMMAND ${CMAKE_COMMAND} -E copy ${_pkg}/changelog.Debian ${_man}/changelog.Debian
  COMMAND gzip -9nf ${_man}/changelog.Debian
  DEPENDS ${_pkg}/changelog.Debian)
add_custom_target(cathbox_app_package_files ALL DEPENDS ${_pages} ${_man}/changelog.Debian.gz)

install(TARGETS ${_programs} RUNTIME DESTINATION bin COMPONENT app)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/cases/ DESTINATION share/cathbox/cases COMPONENT app PATTERN README.md EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/host/device/udev/70-cathbox.rules DESTINATION lib/udev/rules.d COMPONENT app)
install(FILES ${_pkg}/cathbox-trainer.desktop DESTINATION share/applications COMPONENT app)
install(FILES ${_pages} DESTINATION share/man/man1 COMPONENT app)
install(FILES ${_pkg}/copyright ${_man}/changelog.Debian.gz DESTINATION share/doc/cathbox COMPONENT app)
