// Forwarding header: the strength for the relative yield function (Post eq. 66) now lives with
// the models (material/strength.hpp, each model's info.hpp).
#pragma once
#include "material/strength.hpp"
