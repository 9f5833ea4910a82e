#pragma once
// The analytic metric fields of the design (private to rvor_fields). Each factory takes
// already-validated parameters; metric_spec.cpp turns a "NAME:key=value" spec into a call.
// Every field multiplies G by scale^2 (in 2D only the xy block: G(2,2) stays 1).
#include <memory>

#include "rvor/metric_field.h"

namespace rvor::fields {

std::unique_ptr<MetricField> make_euclidean(int dimension, double scale);
// G must be SPD; 2D uniform metrics are given with G(2,2) = 1 and a zero z row/column.
std::unique_ptr<MetricField> make_uniform(int dimension, const Mat3& G, double scale);
std::unique_ptr<MetricField> make_swirl(double scale);                            // 2D
std::unique_ptr<MetricField> make_starred(double scale);                          // 2D
std::unique_ptr<MetricField> make_hyperbolic_shock(int dimension, double scale);  // 2D, 3D
std::unique_ptr<MetricField> make_unidimensional_shock(double scale);             // 2D
std::unique_ptr<MetricField> make_radial_shock_3d(double scale);                  // 3D

}  // namespace rvor::fields
