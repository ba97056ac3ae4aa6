# Installation and packaging, after the module, its wrappings, the plugin and
# the program are defined (included by the root CMakeLists.txt).
#
# What `cmake --install build --prefix P` gives (the build tree has the same
# layout under build/, so everything below also works from there):
#   P/include/DigitalGeometry/                  public headers
#   P/<libdir>/libvtkDigitalGeometry.so*        the module
#   P/<libdir>/cmake/DigitalGeometry/           DigitalGeometryConfig.cmake (+ version, targets)
#   P/bin/piecewise-normals                     the program
#   P/<python>/digitalgeometry/                 the Python package (<python>:
#                                               lib/python3/dist-packages on Debian)
#   P/<libdir>/paraview-5.11/plugins/DigitalGeometryPlugin/  the ParaView plugin
#   P/<libdir>/paraview-5.11/plugins/DigitalGeometry.plugins.xml
#   P/share/doc/digitalgeometry/                LICENSE, CITATION.cff, CHANGELOG.md, README.md
# The module's files come from vtk_module_build (INSTALL_EXPORT), the Python
# package's from vtk_module_wrap_python, the plugin's from
# paraview_plugin_build (PLUGINS_FILE_NAME); this file adds the package
# configuration, the program, the documents and CPack.
include(CMakePackageConfigHelpers)

set(DG_CMAKE_DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/DigitalGeometry")
# Every VTK module the module links, public or private: the exported target
# names them.
set(DG_CONFIG_VTK_COMPONENTS
  CommonCore CommonDataModel CommonExecutionModel CommonMath ParallelCore IOImage zlib)
string(REPLACE ";" " " DG_CONFIG_VTK_COMPONENTS "${DG_CONFIG_VTK_COMPONENTS}")
set(DG_CONFIG_PYTHONPATH "")
if(DG_PYTHON_AVAILABLE)
  set(DG_CONFIG_PYTHONPATH "\${PACKAGE_PREFIX_DIR}/${DG_PYTHON_DESTINATION}")
endif()
set(DG_CONFIG_PLUGIN_DIR "")
if(DG_PLUGIN_AVAILABLE)
  set(DG_CONFIG_PLUGIN_DIR "\${PACKAGE_PREFIX_DIR}/${CMAKE_INSTALL_LIBDIR}/${DG_PLUGIN_SUBDIR}/DigitalGeometryPlugin")
endif()
# One file for the build tree and the install tree: the build tree mirrors the
# install layout, and the prefix is computed from the file's own location.
configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/DigitalGeometryConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/${DG_CMAKE_DESTINATION}/DigitalGeometryConfig.cmake"
  INSTALL_DESTINATION "${DG_CMAKE_DESTINATION}")
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/${DG_CMAKE_DESTINATION}/DigitalGeometryConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${PROJECT_BINARY_DIR}/${DG_CMAKE_DESTINATION}/DigitalGeometryConfig.cmake"
  "${PROJECT_BINARY_DIR}/${DG_CMAKE_DESTINATION}/DigitalGeometryConfigVersion.cmake"
  DESTINATION "${DG_CMAKE_DESTINATION}"
  COMPONENT development)

# The program; its RUNPATH finds the module in ../<libdir> wherever the
# prefix is (VTK's own libraries are in the system's library path).
install(TARGETS piecewise-normals
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
  COMPONENT runtime)

install(FILES
  "${PROJECT_SOURCE_DIR}/LICENSE"
  "${PROJECT_SOURCE_DIR}/CITATION.cff"
  "${PROJECT_SOURCE_DIR}/CHANGELOG.md"
  "${PROJECT_SOURCE_DIR}/README.md"
  DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/digitalgeometry"
  COMPONENT runtime)

# A Debian package (Debian 12, ParaView 5.11's VTK):
#   cpack -G DEB --config build/CPackConfig.cmake
# installs under /usr: /usr/bin/piecewise-normals, the Python package in
# /usr/lib/python3/dist-packages (found by /usr/bin/python3), the plugin in
# /usr/<libdir>/paraview-5.11/plugins/DigitalGeometryPlugin (PV_PLUGIN_PATH,
# README). A package for other machines is built with -DDG_MARCH= (or a
# baseline such as x86-64-v2): the default, "native", is this machine's.
set(CPACK_PACKAGE_NAME "digitalgeometry")
set(CPACK_PACKAGE_VENDOR "DigitalGeometry contributors")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "Digital-surface normals with the Ambrosio-Tortorelli method (VTK module, Python, ParaView plugin, program)")
set(DG_PACKAGE_CONTACT "DigitalGeometry maintainers <digitalgeometry@localhost>" CACHE STRING
  "The .deb's Maintainer field (whoever builds and distributes the package)")
set(CPACK_PACKAGE_CONTACT "${DG_PACKAGE_CONTACT}")
set(CPACK_RESOURCE_FILE_LICENSE "${PROJECT_SOURCE_DIR}/LICENSE")
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
# CPack indents the lines itself (one space).
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
  "Digital surfaces of segmented volumes, integral-invariant, VCM and RHT normals,
Ambrosio-Tortorelli piecewise-smooth normals and sharp features
(Coeurjolly, Foare, Gueth, Lachaud, Computer Graphics Forum 35(7), 2016):
a VTK module (C++ headers and CMake package), its Python package
digitalgeometry, a ParaView plugin and the program piecewise-normals.")
# The module is built against ParaView 5.11's VTK: Debian 12's paraview
# packages carry it (libvtk*-pv5.11), python3-paraview its vtkmodules.
# The libraries' packages (paraview for libvtk*-pv5.11, libc, libstdc++,
# GDCM, CHOLMOD, X11...) come from dpkg-shlibdeps (dpkg-dev, with
# build-essential); without it, paraview is named here. The Python package
# needs python3-paraview's vtkmodules, which no library link shows.
set(_dg_deb_depends "")
find_program(DG_DPKG_SHLIBDEPS dpkg-shlibdeps)
if(DG_DPKG_SHLIBDEPS)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  list(APPEND _dg_deb_depends "paraview (>= 5.11)" "paraview (<< 5.12~)")
endif()
if(DG_PYTHON_AVAILABLE)
  list(APPEND _dg_deb_depends "python3-paraview (>= 5.11)" "python3-paraview (<< 5.12~)" "python3")
endif()
string(REPLACE ";" ", " CPACK_DEBIAN_PACKAGE_DEPENDS "${_dg_deb_depends}")
# To build against the installed CMake package (ParaView's VTK config).
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "paraview-dev")
include(CPack)
