// Must compile: the backend layer looking down into physics/ (the control for
// backend_includes_multi.cpp, so that the failure there is the layer rule, not the setup).
#include "physics/step_stats.hpp"
