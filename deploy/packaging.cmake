# Debian packages of an installation, one per component (cpack -G DEB in the build tree):
#   macsim-common   the DDS profiles, the security templates, macsim_shm_clean
#   macsim          the simulator, its tools and examples, the worlds, the web page, its units
#   kurt-adapter    the robot's computer: kurt_adapter (+ the emulator) and its unit, no rendering
#   macsim-dev      the SDK: headers, static libraries, the CMake package
#   python3-macsim  `import macsim`
# Run-time dependencies are Debian's package names, found by dpkg-shlibdeps from the programs'
# own libraries; the version is the project's.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME macsim)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "MACSim-DDS")
set(CPACK_PACKAGE_CONTACT "MACSim-DDS developers <macsim-dds@users.noreply.localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "MACSim-DDS: the KURT3D robot simulator on ODE, served over DDS")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL common simulator robot dev)
if(MACSIM_BUILD_PYTHON)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)

set(CPACK_DEBIAN_COMMON_PACKAGE_NAME macsim-common)
set(CPACK_DEBIAN_SIMULATOR_PACKAGE_NAME macsim)
set(CPACK_DEBIAN_ROBOT_PACKAGE_NAME kurt-adapter)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME macsim-dev)
set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-macsim)
# Beyond the shared libraries dpkg-shlibdeps finds: the cameras render through Mesa (EGL and
# llvmpipe, loaded at run time) and the discovery server's unit runs Fast DDS's own server; the
# SDK's static libraries need the headers and CMake packages of what they link (of OpenCV, the
# three modules' packages: cmake/macsimOpenCV.cmake finds them without libopencv-dev; spdlog's
# and fmt's for the log, CLI11 is compiled into the command line and not needed); the Python
# module is built for Debian 12's Python 3.11 and hands out numpy arrays.
set(CPACK_DEBIAN_SIMULATOR_PACKAGE_DEPENDS "fastdds-tools, libegl-mesa0, libgl1-mesa-dri")
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libfastrtps-dev (>= 2.9), libfastcdr-dev, libopencv-core-dev, \
libopencv-imgproc-dev, libopencv-ml-dev, libspdlog-dev, libfmt-dev")
set(CPACK_DEBIAN_DEV_PACKAGE_RECOMMENDS "cmake, g++")
set(CPACK_DEBIAN_COMMON_PACKAGE_RECOMMENDS "openssl")  # security/make_security.sh
set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS "python3 (>= 3.11), python3 (<< 3.12), python3-numpy")
# The image codecs' module (lib/macsim/, OpenCV's imgcodecs) is the simulator package's; the
# Python module and the SDK's programs load it when they read or write an image file.
set(CPACK_DEBIAN_PYTHON_PACKAGE_RECOMMENDS "macsim (= ${PROJECT_VERSION})")

include(CPack)
cpack_add_component(common DISPLAY_NAME "MACSim-DDS common files"
  DESCRIPTION "Fast DDS profiles (this machine only; several hosts), DDS Security templates, the shared-memory clean-up")
cpack_add_component(simulator DISPLAY_NAME "MACSim-DDS simulator" DEPENDS common
  DESCRIPTION "macsim (ODE, offscreen rendering), its worlds, the example controllers, the affordance tools, macsim_topic, macsim_web and the service units")
cpack_add_component(robot DISPLAY_NAME "KURT3D adapter" DEPENDS common
  DESCRIPTION "kurt_adapter: the real KURT3D over CAN on the same DDS topics as the simulator, its service unit, and the microcontroller emulator")
cpack_add_component(dev DISPLAY_NAME "MACSim-DDS SDK"
  DESCRIPTION "Headers, static libraries and the CMake package (find_package(macsim)) for controllers built outside the tree")
cpack_add_component(python DISPLAY_NAME "MACSim-DDS Python package"
  DESCRIPTION "import macsim: robots, the supervisor, simulation control and the world state from Python")
