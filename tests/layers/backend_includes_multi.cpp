// Must not compile: the backend layer reaching up into multi/ (tests/CMakeLists.txt builds it
// against the backend's include tree and expects the build to fail).
#include "multi/slab_domain.hpp"
