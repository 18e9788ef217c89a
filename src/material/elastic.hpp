// Forwarding header: the model lives in material/elastic/ (one folder per model).
#pragma once
#include "material/elastic/elastic.hpp"
