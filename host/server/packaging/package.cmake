# The cathbox-server Debian package's files (component `server`; scripts/package runs CPack):
# the program, the admin wrapper, the web pages, the systemd unit, its defaults, the manual page
# made from --help, the docs.
set(_pkg ${CMAKE_CURRENT_SOURCE_DIR}/packaging)
set(_man ${CMAKE_CURRENT_BINARY_DIR}/man)
add_custom_command(OUTPUT ${_man}/cathbox-server.1.gz ${_man}/changelog.Debian.gz
  COMMAND ${CMAKE_COMMAND} -E make_directory ${_man}
  COMMAND ${CMAKE_COMMAND} -DPROGRAM=$<TARGET_FILE:cathbox-server> -DNAME=cathbox-server -DSECTION=1
          "-DSUMMARY=the Cathbox training centre server" -DOUT=${_man}/cathbox-server.1 -P ${PROJECT_SOURCE_DIR}/cmake/help_to_man.cmake
  COMMAND gzip -9nf ${_man}/cathbox-server.1
  COMMAND ${CMAKE_COMMAND} -E copy ${_pkg}/changelog.Debian ${_man}/changelog.Debian
  COMMAND gzip -9nf ${_man}/changelog.Debian
  DEPENDS cathbox-server ${_pkg}/changelog.Debian ${PROJECT_SOURCE_DIR}/cmake/help_to_man.cmake)
add_custom_target(cathbox_server_package_files ALL DEPENDS ${_man}/cathbox-server.1.gz ${_man}/changelog.Debian.gz)

install(TARGETS cathbox-server RUNTIME DESTINATION bin COMPONENT server)
install(PROGRAMS ${_pkg}/cathbox-server-admin DESTINATION sbin COMPONENT server)
install(DIRECTORY web/ DESTINATION share/cathbox-server/web COMPONENT server)
install(FILES ${_pkg}/cathbox-server.service DESTINATION lib/systemd/system COMPONENT server)
install(FILES ${_pkg}/cathbox-server.default DESTINATION /etc/default RENAME cathbox-server COMPONENT server)
install(FILES ${_man}/cathbox-server.1.gz DESTINATION share/man/man1 COMPONENT server)
install(FILES ${_pkg}/copyright ${_man}/changelog.Debian.gz DESTINATION share/doc/cathbox-server COMPONENT server)
install(FILES ${PROJECT_SOURCE_DIR}/docs/server/operating-a-centre.md DESTINATION share/doc/cathbox-server COMPONENT server)
