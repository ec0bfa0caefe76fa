# SPDX-License-Identifier: GPL-3.0-or-later
# A Debian package of the installed tree: `cpack -G DEB` in a configured build folder (after the
# build) writes translucent_<version>_<arch>.deb. Its Depends: line comes from dpkg-shlibdeps on
# the installed binaries and libraries, so it names exactly the shared libraries they link; the
# headers and the CMake package need the -dev packages of the libraries they name, which are
# listed as Recommends (a user who only runs the CLI or the explorer does not need them).
set(CPACK_PACKAGE_NAME translucent)
set(CPACK_PACKAGE_VENDOR "The Translucent developers")
set(CPACK_PACKAGE_CONTACT "The Translucent developers <translucent@localhost>")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Rendering, comparing and validating translucent (subsurface-scattering) materials")
set(CPACK_PACKAGE_DESCRIPTION
    "BSSRDF models, Monte Carlo reference path tracers and real-time subsurface-scattering techniques, with a command line, a Qt explorer and a C++ library.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_LICENSE "GPL-3.0-or-later")
# OpenGL is reached through libepoxy, which opens libEGL at run time: dpkg-shlibdeps cannot see
# it. The Mesa drivers (llvmpipe where there is no GPU), the plots' font and the Python module's
# NumPy are recommended.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libegl1")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS
    "libegl-mesa0, libgl1-mesa-dri, fonts-dejavu-core, python3, python3-numpy, libfmt-dev, nlohmann-json3-dev, libtbb-dev, libglm-dev, libassimp-dev, libembree-dev, libcgal-dev, libopenvdb-dev, libopenimageio-dev, libepoxy-dev, libegl-dev, libssl-dev")
# One package with everything installed (runtime, dev, python components).
set(CPACK_DEB_COMPONENT_INSTALL OFF)
set(CPACK_GENERATOR DEB)
include(CPack)
