# macsim_find_opencv(<module>...): OpenCV's modules as the targets opencv_<module>, from OpenCV's
# own CMake package when there is one (Debian's libopencv-dev, or OpenCV_DIR), else from the
# headers and libraries of Debian's module packages alone (libopencv-core-dev,
# libopencv-imgproc-dev, ...). libopencv-dev depends on every module of OpenCV, with VTK, Qt,
# GDAL and FFmpeg behind them; the four modules MACSim-DDS uses come with a third of the packages
# (deploy/install_deps.sh). Used by the build and by the installed package (macsimConfig.cmake).
macro(macsim_find_opencv)
  find_package(OpenCV QUIET CONFIG COMPONENTS ${ARGV})
  if(NOT OpenCV_FOUND)
    find_path(MACSIM_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4
      DOC "OpenCV's headers (the directory holding opencv2/)")
    if(NOT MACSIM_OPENCV_INCLUDE_DIR)
      message(FATAL_ERROR "OpenCV not found: neither its CMake package (libopencv-dev) nor "
        "opencv2/core.hpp (libopencv-core-dev); deploy/install_deps.sh installs it")
    endif()
    foreach(macsim_opencv_module IN ITEMS ${ARGV})
      set(macsim_opencv_target opencv_${macsim_opencv_module})
      if(NOT TARGET ${macsim_opencv_target})
        find_library(MACSIM_OPENCV_${macsim_opencv_module}_LIBRARY ${macsim_opencv_target}
          DOC "OpenCV's ${macsim_opencv_module} module")
        if(NOT MACSIM_OPENCV_${macsim_opencv_module}_LIBRARY
            OR NOT EXISTS "${MACSIM_OPENCV_INCLUDE_DIR}/opencv2/${macsim_opencv_module}.hpp")
          string(REPLACE "_" "-" macsim_opencv_package "${macsim_opencv_module}")
          message(FATAL_ERROR "OpenCV's ${macsim_opencv_module} module not found (lib"
            "${macsim_opencv_target}.so and opencv2/${macsim_opencv_module}.hpp: Debian's "
            "libopencv-${macsim_opencv_package}-dev); deploy/install_deps.sh installs it")
        endif()
        add_library(${macsim_opencv_target} SHARED IMPORTED)
        set_target_properties(${macsim_opencv_target} PROPERTIES
          IMPORTED_LOCATION "${MACSIM_OPENCV_${macsim_opencv_module}_LIBRARY}"
          INTERFACE_INCLUDE_DIRECTORIES "${MACSIM_OPENCV_INCLUDE_DIR}")
        if(NOT macsim_opencv_module STREQUAL "core")
          # Every module's headers include core's.
          set_target_properties(${macsim_opencv_target} PROPERTIES INTERFACE_LINK_LIBRARIES opencv_core)
        endif()
      endif()
    endforeach()
    string(REPLACE ";" " " macsim_opencv_modules "${ARGV}")
    message(STATUS "OpenCV: the modules ${macsim_opencv_modules} from ${MACSIM_OPENCV_INCLUDE_DIR} "
      "(Debian's module packages; no CMake package of OpenCV)")
  endif()
endmacro()
