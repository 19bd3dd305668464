# Debian packages of mvtrack: `cpack -G DEB` (run in the build directory after building) writes
# one package per install component (CPACK_DEB_COMPONENT_INSTALL), version
# <project version>-<MVTRACK_DEB_REVISION>:
#
#   package                  component     contents                                      Arch
#   mvtrackd                 daemon        bin/mvtrackd, the systemd unit, /etc/mvtrack/  amd64
#                                          (conffiles), DAEMON.md, mvtrackd(8), postinst/
#                                          prerm/postrm (tools/packaging/mvtrackd.*.in)
#   mvtrack-tools            tools         bin/mvtrack, bin/mvtrack-pictures (the only    amd64
#                                          one linking OpenCV), mvtrack(1), mvtrack-CMD(1)
#   mvtrack-spy              spy           bin/mvtrack-spy (lcm-spy launcher), the types  all
#                                          jar share/java/mvtrack_lcmtypes.jar; Java is a
#                                          Depends of this package only
#   python3-mvtrack-lcmtypes python        the Python types in lib/python3/dist-packages  all
#                                          (import mvtrack, Debian's python3) and the
#                                          wheel in share/mvtrack/python (virtualenvs)
#   mvtrack-lcmtypes-dev     lcmtypes_dev  C++ headers include/mvtrack/*.hpp, the .lcm    all
#                                          files in share/mvtrack/lcmtypes
#   mvtrack                  meta          nothing but its copyright: Depends on mvtrackd all
#                                          and mvtrack-tools, Recommends the other three,
#                                          all (= this version); it replaces the single
#                                          package mvtrack 0.2.0 of earlier builds
#
# Every package has share/doc/<package>/copyright (tools/packaging/copyright, DEP-5; no license
# has been chosen: docs/DECISIONS.md "Packaging"). The choices (what is enabled on install, the
# reload command, where the Python types and headers go, the man pages) are in
# docs/DECISIONS.md "Packaging"; tests/package checks all of it on the built packages, and
# tools/dev/deb_chroot_test.sh installs them into a fresh Debian 12 (on demand: it downloads).
#
# Paths: the packages install under CMAKE_INSTALL_PREFIX. The daemon's install rules bake that
# prefix into the systemd unit (ExecStart) and put the example configuration in
# CMAKE_INSTALL_FULL_SYSCONFDIR, so configure with -DCMAKE_INSTALL_PREFIX=/usr (the ci preset
# does) for packages that follow Debian policy (binaries in /usr/bin, unit in
# /usr/lib/systemd/system, config in /etc/mvtrack, man pages in /usr/share/man). Any other
# prefix gives consistent packages under that prefix.
#
# Dependencies: dpkg-shlibdeps (Debian package dpkg-dev) computes each package's Depends from its
# own ELF files' shared libraries (mvtrackd: liblcm1, libspdlog, libsystemd0, libyaml-cpp, the
# C/C++ runtime; mvtrack-tools: also OpenCV and civetweb); the Depends written here are the
# ones no ELF file shows (Java for mvtrack-spy, python3, liblcm-dev).
#
# Man pages: help2man writes them at build time from the programs' own --help and --version
# (tools/packaging/make_man_pages.sh, target mvtrack_man_pages, gzipped). help2man is required
# unless the build is configured with -DMVTRACK_MAN_PAGES=OFF (the release preset), and then
# cpack refuses to build packages (no package goes out without its man pages); so it does
# without mvtrack-pictures. The `package` preset builds everything the packages hold.

include(GNUInstallDirs)

set(MVTRACK_DEB_REVISION 1 CACHE STRING
    "Debian revision of the packages: their version is <project version>-<this>")
set(MVTRACK_DEB_VERSION ${PROJECT_VERSION}-${MVTRACK_DEB_REVISION})
option(MVTRACK_MAN_PAGES "Generate the man pages with help2man (needed to build packages)" ON)

set(_pkg_src ${PROJECT_SOURCE_DIR}/tools/packaging)
set(_pkg_out ${PROJECT_BINARY_DIR}/cpack)
set(MVTRACK_UNIT mvtrackd.service)
set(MVTRACK_CONFIG_DIR ${CMAKE_INSTALL_FULL_SYSCONFDIR}/mvtrack)
set(MVTRACK_DOC_DIR ${CMAKE_INSTALL_FULL_DATAROOTDIR}/doc/mvtrackd)
if(IS_ABSOLUTE "${MVTRACK_SYSTEMD_UNIT_DIR}")
  set(MVTRACK_UNIT_PATH ${MVTRACK_SYSTEMD_UNIT_DIR}/${MVTRACK_UNIT})
else()
  set(MVTRACK_UNIT_PATH ${CMAKE_INSTALL_PREFIX}/${MVTRACK_SYSTEMD_UNIT_DIR}/${MVTRACK_UNIT})
endif()
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
  ${_pkg_src}/mvtrackd.postinst.in ${_pkg_src}/mvtrackd.prerm.in ${_pkg_src}/mvtrackd.postrm.in
  ${_pkg_src}/python3-mvtrack-lcmtypes.postinst ${_pkg_src}/python3-mvtrack-lcmtypes.prerm
  ${_pkg_src}/mvtrackd.h2m.in ${_pkg_src}/mvtrack.h2m.in)

# ---------------------------------------------------------------------------------------------
# Man pages (help2man, at build time).
if(TARGET mvtrack AND TARGET mvtrackd AND TARGET mvtrack-pictures AND MVTRACK_MAN_PAGES)
  find_program(MVTRACK_HELP2MAN help2man)
  if(NOT MVTRACK_HELP2MAN)
    message(FATAL_ERROR
      "help2man not found: the man pages mvtrack(1) and mvtrackd(8) are generated with it. "
      "Install the Debian package help2man (tools/dev/install_deps.sh installs it), or "
      "configure with -DMVTRACK_MAN_PAGES=OFF for a build that is not packaged (cpack then "
      "refuses to build the packages).")
  endif()
  set(_man_dir ${PROJECT_BINARY_DIR}/man)
  configure_file(${_pkg_src}/mvtrackd.h2m.in ${_man_dir}/h2m/mvtrackd.h2m @ONLY)
  configure_file(${_pkg_src}/mvtrack-stitcher.h2m.in ${_man_dir}/h2m/mvtrack-stitcher.h2m @ONLY)
  configure_file(${_pkg_src}/mvtrack.h2m.in ${_man_dir}/h2m/mvtrack.h2m @ONLY)
  configure_file(${_pkg_src}/mvtrack-command.h2m ${_man_dir}/h2m/mvtrack-command.h2m COPYONLY)
  add_custom_command(
    OUTPUT ${_man_dir}/man1/mvtrack.1.gz ${_man_dir}/man8/mvtrackd.8.gz
    COMMAND bash ${_pkg_src}/make_man_pages.sh ${MVTRACK_HELP2MAN} ${_man_dir}
            $<TARGET_FILE:mvtrack> $<TARGET_FILE:mvtrackd> ${_man_dir}/h2m ${PROJECT_SOURCE_DIR}
    DEPENDS mvtrack mvtrack-pictures mvtrackd mvtrack-stitcher ${_pkg_src}/make_man_pages.sh
            ${_man_dir}/h2m/mvtrackd.h2m ${_man_dir}/h2m/mvtrack.h2m
            ${_man_dir}/h2m/mvtrack-stitcher.h2m
            ${_man_dir}/h2m/mvtrack-command.h2m
    COMMENT "help2man: mvtrack(1), mvtrack-<command>(1), mvtrackd(8), mvtrack-stitcher(8)"
    VERBATIM)
  add_custom_target(mvtrack_man_pages ALL
                    DEPENDS ${_man_dir}/man1/mvtrack.1.gz ${_man_dir}/man8/mvtrackd.8.gz)
  install(DIRECTORY ${_man_dir}/man1 DESTINATION ${CMAKE_INSTALL_MANDIR} COMPONENT tools)
  install(DIRECTORY ${_man_dir}/man8 DESTINATION ${CMAKE_INSTALL_MANDIR} COMPONENT daemon)
  set(CPACK_MVTRACK_MAN_PAGES ON)
else()
  set(CPACK_MVTRACK_MAN_PAGES OFF)
endif()

# ---------------------------------------------------------------------------------------------
# Control files: mvtrackd's conffiles and maintainer scripts, python3-mvtrack-lcmtypes' scripts.
file(MAKE_DIRECTORY ${_pkg_out}/daemon ${_pkg_out}/python)
file(WRITE ${_pkg_out}/daemon/conffiles.new
     "${MVTRACK_CONFIG_DIR}/calibration.example.yaml\n${MVTRACK_CONFIG_DIR}/mvtrackd.yaml\n")
configure_file(${_pkg_out}/daemon/conffiles.new ${_pkg_out}/daemon/conffiles COPYONLY)
foreach(script postinst prerm postrm)
  configure_file(${_pkg_src}/mvtrackd.${script}.in ${_pkg_out}/daemon/${script} @ONLY)
endforeach()
foreach(script postinst prerm)
  configure_file(${_pkg_src}/python3-mvtrack-lcmtypes.${script} ${_pkg_out}/python/${script}
                 COPYONLY)
endforeach()

# ---------------------------------------------------------------------------------------------
# The packages: those whose programs this build has (no mvtrack-spy with MVTRACK_BUILD_JAVA=OFF,
# no Python package without a Python interpreter). tests/package reads the list.
set(_components "")
foreach(pair daemon:mvtrackd tools:mvtrack spy:mvtrack_lcmtypes_java
             python:mvtrack_lcmtypes_python_dist lcmtypes_dev:mvtrack_lcmtypes_cpp)
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 c)
  list(GET pair 1 t)
  if(TARGET ${t})
    list(APPEND _components ${c})
  endif()
endforeach()
if(daemon IN_LIST _components AND tools IN_LIST _components)
  list(APPEND _components meta)
endif()
set(_name_daemon mvtrackd)
set(_name_tools mvtrack-tools)
set(_name_spy mvtrack-spy)
set(_name_python python3-mvtrack-lcmtypes)
set(_name_lcmtypes_dev mvtrack-lcmtypes-dev)
set(_name_meta mvtrack)
set(_package_list "")
foreach(c IN LISTS _components)
  install(FILES ${_pkg_src}/copyright DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${_name_${c}}
          COMPONENT ${c})
  string(APPEND _package_list "${_name_${c}}\n")
endforeach()
file(WRITE ${_pkg_out}/packages.txt.new "${_package_list}")
configure_file(${_pkg_out}/packages.txt.new ${_pkg_out}/packages.txt COPYONLY)

set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL ${_components})
set(CPACK_PACKAGE_NAME mvtrack)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEBIAN_PACKAGE_RELEASE ${MVTRACK_DEB_REVISION})
set(CPACK_PACKAGE_VENDOR "mvtrack")
set(CPACK_PACKAGE_CONTACT "mvtrack maintainers <mvtrack@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS OFF)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
foreach(c IN LISTS _components)
  string(TOUPPER ${c} C)
  set(CPACK_DEBIAN_${C}_PACKAGE_NAME ${_name_${c}})
  # Files of the single package `mvtrack` of earlier builds (version 0.2.0) move here.
  if(NOT c STREQUAL meta)
    set(CPACK_DEBIAN_${C}_PACKAGE_BREAKS "mvtrack (<< ${MVTRACK_DEB_VERSION}~)")
    set(CPACK_DEBIAN_${C}_PACKAGE_REPLACES "mvtrack (<< ${MVTRACK_DEB_VERSION}~)")
  endif()
endforeach()
foreach(c spy python lcmtypes_dev meta)
  string(TOUPPER ${c} C)
  set(CPACK_DEBIAN_${C}_PACKAGE_ARCHITECTURE all)
  set(CPACK_DEBIAN_${C}_PACKAGE_SHLIBDEPS OFF)
endforeach()

set(CPACK_DEBIAN_DAEMON_PACKAGE_SECTION science)
set(CPACK_DEBIAN_DAEMON_PACKAGE_SUGGESTS "mvtrack-tools")
set(CPACK_DEBIAN_DAEMON_PACKAGE_CONTROL_EXTRA
    "${_pkg_out}/daemon/conffiles;${_pkg_out}/daemon/postinst;${_pkg_out}/daemon/prerm;${_pkg_out}/daemon/postrm")
set(CPACK_DEBIAN_DAEMON_DESCRIPTION
"multi-view multi-person 3D tracker: the LCM daemon
mvtrackd turns synchronized 2D person detections of calibrated cameras (boxes or
2D poses), received over LCM, into 3D person tracks (footprints or 3D poses)
published over LCM, with a status message every second. It runs as a hardened
systemd service (Type=notify with a watchdog, a dynamic unprivileged user).

The service is neither enabled nor started on installation: it needs the
site's calibration first (${MVTRACK_CONFIG_DIR}/mvtrackd.yaml, mvtrackd(8)).
The tools to check its configuration and watch it are in mvtrack-tools.")

set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION science)
set(CPACK_DEBIAN_TOOLS_PACKAGE_SUGGESTS "mvtrackd")
set(CPACK_DEBIAN_TOOLS_DESCRIPTION
"multi-view multi-person 3D tracker: command-line tools
mvtrack replays detection recordings exactly as the daemon mvtrackd tracks them,
converts datasets and detector outputs (Shelf, Campus, Panoptic, WILDTRACK,
MOTChallenge, COCO keypoints, JSON lines), evaluates tracks (CLEAR MOT, IDF1,
HOTA, MPJPE, PCP), simulates recordings, benchmarks, checks configurations and
calibrations, serves a live web view with Prometheus metrics, and draws
pictures and videos (in mvtrack-pictures, which links OpenCV).")

set(CPACK_DEBIAN_SPY_PACKAGE_SECTION science)
set(CPACK_DEBIAN_SPY_PACKAGE_DEPENDS
    "default-jre | java8-runtime, liblcm-java, libjchart2d-java")
set(CPACK_DEBIAN_SPY_DESCRIPTION
"lcm-spy with the mvtrack LCM message types
mvtrack-spy opens LCM's lcm-spy with the message types of mvtrack (detections,
tracks, status) decodable. Includes the Java types jar
(${CMAKE_INSTALL_FULL_DATADIR}/java/mvtrack_lcmtypes.jar).")

set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS "python3:any")
set(CPACK_DEBIAN_PYTHON_PACKAGE_CONTROL_EXTRA "${_pkg_out}/python/postinst;${_pkg_out}/python/prerm")
set(CPACK_DEBIAN_PYTHON_DESCRIPTION
"mvtrack LCM message types for Python 3
The lcm-gen Python types of mvtrack's messages (import mvtrack: tracks3d_t,
camera_detections_t, tracker_status_t, ...). Encoding and decoding needs only
the standard library; talking to LCM needs PyPI's lcm (Debian 12 has no
python3-lcm). The wheel, for virtual environments, is in
${CMAKE_INSTALL_FULL_DATADIR}/mvtrack/python.")

set(CPACK_DEBIAN_LCMTYPES_DEV_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_LCMTYPES_DEV_PACKAGE_DEPENDS "liblcm-dev")
set(CPACK_DEBIAN_LCMTYPES_DEV_DESCRIPTION
"mvtrack LCM message types: C++ headers and .lcm files
The lcm-gen C++ headers of mvtrack's messages (<mvtrack/tracks3d_t.hpp>, ...)
for programs that publish detections to mvtrackd or consume its tracks, and
the .lcm definitions for other languages
(${CMAKE_INSTALL_FULL_DATADIR}/mvtrack/lcmtypes).")

set(CPACK_DEBIAN_META_PACKAGE_SECTION metapackages)
set(CPACK_DEBIAN_META_PACKAGE_DEPENDS
    "mvtrackd (= ${MVTRACK_DEB_VERSION}), mvtrack-tools (= ${MVTRACK_DEB_VERSION})")
set(_recommends "")
foreach(c spy python lcmtypes_dev)
  if(c IN_LIST _components)
    list(APPEND _recommends "${_name_${c}} (= ${MVTRACK_DEB_VERSION})")
  endif()
endforeach()
string(REPLACE ";" ", " CPACK_DEBIAN_META_PACKAGE_RECOMMENDS "${_recommends}")
set(CPACK_DEBIAN_META_DESCRIPTION
"multi-view multi-person 3D tracker (metapackage)
Installs the daemon (mvtrackd) and the command-line tools (mvtrack-tools), and
recommends the lcm-spy launcher (mvtrack-spy, Java), the Python types and the
C++ headers. Builds up to version 0.2.0 made one package of this name holding
all of them; this one upgrades such an installation to the split packages.")

if(NOT CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  message(STATUS "packaging: CMAKE_INSTALL_PREFIX is ${CMAKE_INSTALL_PREFIX}; the .debs install "
                 "under it (configure with -DCMAKE_INSTALL_PREFIX=/usr for Debian packages)")
endif()

# No packages without man pages (MVTRACK_MAN_PAGES=OFF, or no mvtrack-pictures, whose commands
# the pages document): refused before anything is packaged.
file(WRITE ${_pkg_out}/check_man_pages.cmake [=[
# Generated by tools/cmake/packaging.cmake: cpack refuses a build without man pages.
if(NOT CPACK_MVTRACK_MAN_PAGES)
  message(FATAL_ERROR "this build has no man pages (configured with MVTRACK_MAN_PAGES=OFF or "
                      "without the programs, mvtrack-pictures among them): build with the "
                      "package preset (tools/dev/install_deps.sh package; cmake --preset "
                      "package; cmake --build --preset package), then run cpack")
endif()
]=])
set(CPACK_PRE_BUILD_SCRIPTS ${_pkg_out}/check_man_pages.cmake)

include(CPack)
