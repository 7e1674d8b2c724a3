# Debian packages with CPack (scripts/package). Today: cathbox-server (component `server`,
# installed by host/server/packaging/package.cmake).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL server)
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
include(CPack)
