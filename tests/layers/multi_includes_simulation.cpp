// Must not compile: multi/ reaching up into the simulation layer.
#include "simulation.hpp"
