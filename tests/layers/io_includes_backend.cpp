// Must not compile: io/ (beside the solver's stack, on core only) reaching into backend/.
#include "backend/subdomain.hpp"
