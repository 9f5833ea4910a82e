// The "NAME[:key=value,...]" spec of an analytic metric field (uniform also takes its tensor
// components positionally: "uniform:m11,m12,m22[,scale=S]"). Every problem is reported as one line
// "metric 'SPEC': PROBLEM" so that the CLI can print it as is.
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analytic_fields.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

struct FieldArguments {
  int dimension = 3;
  double scale = 1;
  Mat3 tensor = Mat3::Identity();  // uniform only
};

using Builder = std::unique_ptr<MetricField> (*)(const FieldArguments&);

struct FieldKind {
  const char* name;
  bool in_2d;
  bool in_3d;
  bool takes_tensor;  // positional tensor components (uniform)
  Builder build;
};

const std::array<FieldKind, 7> kFieldKinds = {{
    {"euclidean", true, true, false,
     [](const FieldArguments& a) { return fields::make_euclidean(a.dimension, a.scale); }},
    {"uniform", true, true, true,
     [](const FieldArguments& a) { return fields::make_uniform(a.dimension, a.tensor, a.scale); }},
    {"swirl", true, false, false,
     [](const FieldArguments& a) { return fields::make_swirl(a.scale); }},
    {"starred", true, false, false,
     [](const FieldArguments& a) { return fields::make_starred(a.scale); }},
    {"hyperbolic_shock", true, true, false,
     [](const FieldArguments& a) { return fields::make_hyperbolic_shock(a.dimension, a.scale); }},
    {"unidimensional_shock", true, false, false,
     [](const FieldArguments& a) { return fields::make_unidimensional_shock(a.scale); }},
    {"radial_shock_3d", false, true, false,
     [](const FieldArguments& a) { return fields::make_radial_shock_3d(a.scale); }},
}};

const char* const kKnownKeys = "scale";

class SpecParser {
 public:
  SpecParser(std::string spec, int dimension) : spec_(std::move(spec)), dimension_(dimension) {}

  std::unique_ptr<MetricField> parse() {
    if (dimension_ != 2 && dimension_ != 3)
      fail("dimension " + std::to_string(dimension_) + " is not 2 or 3");
    const std::size_t colon = spec_.find(':');
    const FieldKind& kind = find_kind(trim_blanks(spec_.substr(0, colon)));
    check_dimension(kind);
    if (colon != std::string::npos) parse_parameters(spec_.substr(colon + 1), kind);
    FieldArguments arguments;
    arguments.dimension = dimension_;
    arguments.scale = scale_.value_or(1.0);
    if (kind.takes_tensor) arguments.tensor = uniform_tensor();
    return kind.build(arguments);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw Error("metric '" + spec_ + "': " + problem);
  }

  const FieldKind& find_kind(const std::string& name) const {
    for (const FieldKind& kind : kFieldKinds)
      if (name == kind.name) return kind;
    std::string known;
    for (const std::string& each : analytic_metric_names())
      known += (known.empty() ? "" : ", ") + each;
    fail("unknown field '" + name + "' (known: " + known + ")");
  }

  // A field without a form in the domain's dimension names both ways out: a domain of the field's
  // dimension, or a field of the domain's.
  void check_dimension(const FieldKind& kind) const {
    const bool fits = dimension_ == 2 ? kind.in_2d : kind.in_3d;
    if (fits) return;
    std::string fields;
    for (const FieldKind& other : kFieldKinds)
      if (dimension_ == 2 ? other.in_2d : other.in_3d)
        fields += (fields.empty() ? "" : ", ") + std::string(other.name);
    const std::string domains =
        dimension_ == 2 ? "box:, a mesh: or a 3D implicit: shape" : "rect: or implicit:disk";
    fail("'" + std::string(kind.name) + "' is a " + (dimension_ == 2 ? "3D" : "2D") +
         " field, the domain is " + std::to_string(dimension_) + "D: give it a " +
         (dimension_ == 2 ? "3D" : "2D") + " domain (" + domains + "), or a field with a " +
         std::to_string(dimension_) + "D form (" + fields + ")");
  }

  void parse_parameters(const std::string& list, const FieldKind& kind) {
    if (trim_blanks(list).empty()) return;  // "swirl:" means no parameters
    for (const std::string& token : split_commas(list)) parse_parameter(trim_blanks(token), kind);
  }

  void parse_parameter(const std::string& token, const FieldKind& kind) {
    if (token.empty()) fail("empty parameter (two commas in a row, or a trailing comma?)");
    const std::size_t equals = token.find('=');
    if (equals == std::string::npos) {
      if (!kind.takes_tensor)
        fail("expected key=value, got '" + token + "' (known keys: " + kKnownKeys + ")");
      components_.push_back(token);
      return;
    }
    const std::string key = trim_blanks(token.substr(0, equals));
    const std::string value = trim_blanks(token.substr(equals + 1));
    if (key != "scale") fail("unknown key '" + key + "' (known: " + kKnownKeys + ")");
    if (scale_) fail("key 'scale' is given twice");
    const std::optional<double> scale = parse_decimal(value);
    if (!scale || !(*scale > 0))
      fail("scale must be a positive finite number, got '" + value + "'");
    scale_ = scale;
  }

  // The tensor of `uniform`: m11,m12,m22 in 2D; m11,m12,m22,m13,m23,m33 (.sol order) in 3D.
  Mat3 uniform_tensor() const {
    const std::size_t expected = dimension_ == 2 ? 3 : 6;
    if (components_.size() != expected)
      fail("uniform needs " + std::to_string(expected) + " components (" +
           (dimension_ == 2 ? "m11,m12,m22" : "m11,m12,m22,m13,m23,m33") + ") for a " +
           std::to_string(dimension_) + "D domain, got " + std::to_string(components_.size()));
    SolTensor sol = {0, 0, 0, 0, 0, 1};  // 2D: zero z row and column, G(2,2) = 1
    for (std::size_t i = 0; i < expected; ++i) {
      const std::optional<double> value = parse_decimal(components_[i]);
      if (!value)
        fail("component " + std::to_string(i + 1) + " '" + components_[i] +
             "' is not a finite number");
      sol[i] = *value;
    }
    const Mat3 G = tensor_from_sol(sol);
    const std::string problem = metric_problem(G, dimension_);
    if (!problem.empty()) fail("the uniform tensor " + problem);
    return G;
  }

  std::string spec_;
  int dimension_;
  std::optional<double> scale_;
  std::vector<std::string> components_;
};

}  // namespace

std::unique_ptr<MetricField> make_analytic_metric(const std::string& spec, int dimension) {
  return SpecParser(spec, dimension).parse();
}

std::vector<std::string> analytic_metric_names() {
  std::vector<std::string> names;
  for (const FieldKind& kind : kFieldKinds) names.emplace_back(kind.name);
  return names;
}

}  // namespace rvor
