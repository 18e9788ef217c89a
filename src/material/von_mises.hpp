// Forwarding header: the model lives in material/von_mises/ (one folder per model).
#pragma once
#include "material/von_mises/von_mises.hpp"
