# Install layout and Debian packages (CPack DEB), for a Debian 12 board:
#   handscan            (component runtime):  the daemon, the kiosk UI, the device's `handscan`
#                        tool, /etc/handscan, systemd units + target, udev rules, tmpfiles,
#                        systemd-networkd links, the kiosk's PAM service; maintainer scripts make
#                        the users and enable the units (packaging/debian/).
#   handscan-dev-tools  (component devtools): `handscan-dev`, the full tool with the simulator
#                        and the evaluation (sim, eval), for a development host.
# Paths are Debian 12's (units and udev rules under /lib, as dpkg's merged-/usr rules want).
# `cpack --config build/ci/CPackConfig.cmake` packs the already-built tree; tests/e2e/package checks
# the packages (layout, unit verification, security exposure, a daemon started from them).
set(HANDSCAN_UNIT_DIR /lib/systemd/system)
set(HANDSCAN_NETWORK_DIR /lib/systemd/network)
set(HANDSCAN_UDEV_RULES_DIR /lib/udev/rules.d)
set(HANDSCAN_TMPFILES_DIR /usr/lib/tmpfiles.d)
set(HANDSCAN_DOC_DIR /usr/share/doc/handscan)

# The device's `handscan`: every subcommand that needs neither the simulator nor the evaluation
# (tools/sim, tools/eval: Embree, the scenes), i.e. each cmd_*.cpp that includes no header of
# theirs. With HANDSCAN_WITH_DEV_TOOLS (wt/hygiene) sim and eval live in cli/dev/ and their
# libraries on HANDSCAN_CLI_DEV_LIBS, and these filters find nothing more to take out.
# Every source of the tool but main.cpp (subcommands, decoders and their helpers such as
# info_e57.cpp), so a helper added to firmware/cli/ comes along without an edit here.
file(GLOB _cli_sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/firmware/cli/*.cpp)
list(FILTER _cli_sources EXCLUDE REGEX "/main\\.cpp$")
set(_device_cli_sources)
foreach(_source IN LISTS _cli_sources)
  file(STRINGS ${_source} _dev_includes REGEX "#include \"handscan/(sim|eval)/")
  if(NOT _dev_includes)
    list(APPEND _device_cli_sources ${_source})
  endif()
endforeach()
get_property(_device_cli_libs GLOBAL PROPERTY HANDSCAN_CLI_LIBS)
list(REMOVE_ITEM _device_cli_libs handscan::sim handscan::eval)
add_executable(handscan-device ${CMAKE_SOURCE_DIR}/firmware/cli/main.cpp ${_device_cli_sources})
target_include_directories(handscan-device PRIVATE ${CMAKE_SOURCE_DIR}/firmware/cli)
target_link_libraries(handscan-device PRIVATE handscan::core CLI11::CLI11 ${_device_cli_libs})
set_target_properties(handscan-device PROPERTIES OUTPUT_NAME handscan
                      RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/device)
handscan_set_warnings(handscan-device)

# What the package needs built (tests/e2e/package builds this, not the whole tree).
add_custom_target(handscan-package-binaries)
add_dependencies(handscan-package-binaries handscan-pipeline handscan-device handscan)
if(TARGET handscan-ui)
  add_dependencies(handscan-package-binaries handscan-ui)
endif()

install(TARGETS handscan-device RUNTIME DESTINATION bin COMPONENT runtime)
install(FILES config/device.yaml config/calibration.yaml config/camchain.yaml
        DESTINATION /etc/handscan COMPONENT runtime)
install(FILES systemd/handscan.target systemd/handscan-pipeline.service
              systemd/handscan-ui.service systemd/handscan-usb-mount@.service
              systemd/handscan-usb-eject.path systemd/handscan-usb-eject.service
        DESTINATION ${HANDSCAN_UNIT_DIR} COMPONENT runtime)
install(FILES systemd/network/10-handscan-laser.link systemd/network/80-handscan-laser.network
              systemd/network/80-handscan-can0.network
        DESTINATION ${HANDSCAN_NETWORK_DIR} COMPONENT runtime)
install(FILES systemd/60-handscan.rules systemd/61-handscan-usb.rules
        DESTINATION ${HANDSCAN_UDEV_RULES_DIR} COMPONENT runtime)
install(FILES systemd/handscan.tmpfiles.conf DESTINATION ${HANDSCAN_TMPFILES_DIR}
        RENAME handscan.conf COMPONENT runtime)
install(FILES systemd/handscan-kiosk.pam DESTINATION /etc/pam.d RENAME handscan-kiosk
        COMPONENT runtime)
install(FILES README.md DESTINATION ${HANDSCAN_DOC_DIR} COMPONENT runtime)
install(FILES systemd/README.md DESTINATION ${HANDSCAN_DOC_DIR} RENAME units.md COMPONENT runtime)
install(FILES README.md DESTINATION /usr/share/doc/handscan-dev-tools COMPONENT devtools)
file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/device)
file(CREATE_LINK ../lib/handscan/dev/handscan ${CMAKE_BINARY_DIR}/device/handscan-dev SYMBOLIC)
install(FILES ${CMAKE_BINARY_DIR}/device/handscan-dev DESTINATION bin COMPONENT devtools)

set(CPACK_PACKAGE_NAME handscan)
set(CPACK_PACKAGE_VENDOR "handscan")
set(CPACK_PACKAGE_CONTACT "handscan maintainers <handscan@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "handheld spinning-laser 3D scanner firmware")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL runtime devtools)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_COMPRESSION_TYPE gzip)  # fast to build in CI; the binaries are stripped
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME handscan)
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION
    "handscan scanner appliance: pipeline daemon, kiosk UI, units\n The real-time daemon \
(drivers, laser-inertial odometry, live map, journal), the touch-screen UI as a cage kiosk, \
systemd units under handscan.target, udev rules, USB stick mounting and networkd links.")
# shlibdeps adds the libraries; these are the programs the units and scripts run.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS
    "adduser, systemd (>= 252), udev, init-system-helpers, mount, cage, xwayland, fonts-dejavu-core, libpam-systemd")
# report.pdf beside report.html on every export, where weasyprint is installed (heavy: Python).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "weasyprint")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA
    ${CMAKE_SOURCE_DIR}/packaging/debian/postinst ${CMAKE_SOURCE_DIR}/packaging/debian/prerm
    ${CMAKE_SOURCE_DIR}/packaging/debian/postrm ${CMAKE_SOURCE_DIR}/packaging/debian/conffiles)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_DEVTOOLS_PACKAGE_NAME handscan-dev-tools)
set(CPACK_DEBIAN_DEVTOOLS_DESCRIPTION
    "handscan development tools: simulator and evaluation\n handscan-dev: the handscan tool with \
the digital twin (handscan-dev sim) and the accuracy evaluation (handscan-dev eval).")
set(CPACK_DEBIAN_DEVTOOLS_PACKAGE_SECTION devel)
include(CPack)
