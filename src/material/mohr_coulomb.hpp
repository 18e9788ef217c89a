// Forwarding header: the model lives in material/mohr_coulomb/ (one folder per model).
#pragma once
#include "material/mohr_coulomb/mohr_coulomb.hpp"
