// Forwarding header: each model's parameters live in its folder.
#pragma once
#include "material/mohr_coulomb/params.hpp"
#include "material/von_mises/params.hpp"
