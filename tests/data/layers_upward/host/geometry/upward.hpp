// A file against the layer order, for test layer_order_catches_upward: geometry includes spacing.
#pragma once
#include "geometry/geometry.hpp"
#include "spacing/spacing_field.hpp"
