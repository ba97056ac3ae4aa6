# Injected with CMAKE_PROJECT_INCLUDE: DGtal 2.x fetches Boost 1.84 with CPM
# (network); we have no network, so give it Debian's Boost (1.74) instead.
# DGtal's cmake/deps/boost.cmake returns early when Boost::headers exists.
find_package(Boost 1.74 REQUIRED)
