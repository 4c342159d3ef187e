#include "harness/metrics/registry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "common/io/stable_json.h"

namespace corridorsim {
namespace metrics {
namespace {

using Json = nlohmann::ordered_json;
using slam::LandmarkType;

// ---- Declarations -------------------------------------------------------------------------------
// The table is registry.def (an X-macro list); these are the groups and fields it builds. A group
// shares a section, a scope and a path prefix; a prefix may hold one placeholder (<type>, <d>)
// that expands over `values`, each value over all of the group's fields in order (this order is
// MetricNames()'). A field limited to some values (`only`) is declared for those alone.

struct Field {
  std::string name;
  MetricUnit unit = MetricUnit::kCount;
  std::string meaning;
  std::vector<std::string> only;  // placeholder values the field exists for; empty: all
  bool map = false;
  bool absent_when_zero = false;
};

struct Group {
  Group(std::string section_in, MetricScope scope_in, std::string prefix_in,
        std::string placeholder_in = "", std::vector<std::string> values_in = {})
      : section(std::move(section_in)),
        scope(scope_in),
        prefix(std::move(prefix_in)),
        placeholder(std::move(placeholder_in)),
        values(std::move(values_in)) {}
  Group& Add(const char* name, MetricUnit unit, const char* meaning) {
    fields.push_back({name, unit, meaning, {}, false, false});
    return *this;
  }
  // An object keyed by names (stages, cameras) whose entries share the unit.
  Group& AddMap(const char* name, MetricUnit unit, const char* meaning) {
    Add(name, unit, meaning).fields.back().map = true;
    return *this;
  }
  // Declared for these placeholder values only.
  Group& AddFor(std::vector<std::string> only, const char* name, MetricUnit unit,
                const char* meaning) {
    Add(name, unit, meaning).fields.back().only = std::move(only);
    return *this;
  }
  // A health counter written only when non-zero (a healthy run's metrics.json keeps its bytes).
  Group& AddAbsentWhenZero(const char* name, MetricUnit unit, const char* meaning) {
    Add(name, unit, meaning).fields.back().absent_when_zero = true;
    return *this;
  }

  std::string section;
  MetricScope scope;
  std::string prefix;               // e.g. "map.<type>."
  std::string placeholder;          // "<type>", "<d>" or empty
  std::vector<std::string> values;  // what the placeholder expands to
  std::vector<Field> fields;
};

std::vector<std::string> TypeNames(const LandmarkType* begin, const LandmarkType* end) {
  std::vector<std::string> names;
  for (const LandmarkType* t = begin; t != end; ++t) names.push_back(slam::LandmarkTypeName(*t));
  return names;
}

std::vector<Group> Declarations() {
  const std::vector<std::string> all_types = TypeNames(std::begin(kAllTypes), std::end(kAllTypes));
  const std::vector<std::string> map_types = TypeNames(std::begin(kMapTypes), std::end(kMapTypes));
  std::vector<std::string> rpe_distances;
  for (const int d : kRpeDistancesM) rpe_distances.push_back(std::to_string(d));
  const std::vector<std::string> detector_types = {"door_plate", "lamp", "door"};

  std::vector<Group> groups;
#define METRICS_GROUP(section, scope, prefix) \
  groups.emplace_back(section, MetricScope::scope, prefix);
#define METRICS_GROUP_OVER(section, scope, prefix, placeholder, values) \
  groups.emplace_back(section, MetricScope::scope, prefix, placeholder, values);
#define METRIC(name, unit, meaning) groups.back().Add(name, MetricUnit::unit, meaning);
#define METRIC_MAP(name, unit, meaning) groups.back().AddMap(name, MetricUnit::unit, meaning);
#define METRIC_FOR(name, unit, meaning, ...) \
  groups.back().AddFor({__VA_ARGS__}, name, MetricUnit::unit, meaning);
#define METRIC_ABSENT_WHEN_ZERO(name, unit, meaning) \
  groups.back().AddAbsentWhenZero(name, MetricUnit::unit, meaning);
#include "harness/metrics/registry.def"
  return groups;
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  if (from.empty()) return text;
  const auto at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

struct Registry {
  std::vector<MetricSpec> specs;
  std::map<std::pair<MetricScope, std::string>, std::size_t> index;
  std::vector<std::string> sections;
};

const Registry& TheRegistry() {
  static const Registry registry = [] {
    Registry r;
    for (const Group& g : Declarations()) {
      if (std::find(r.sections.begin(), r.sections.end(), g.section) == r.sections.end()) {
        r.sections.push_back(g.section);
      }
      const std::vector<std::string> values =
          g.placeholder.empty() ? std::vector<std::string>{""} : g.values;
      for (const std::string& value : values) {
        for (const Field& f : g.fields) {
          if (!f.only.empty() && std::find(f.only.begin(), f.only.end(), value) == f.only.end()) {
            continue;
          }
          MetricSpec spec{Replace(g.prefix, g.placeholder, value) + f.name + (f.map ? ".*" : ""),
                          g.prefix + f.name + (f.map ? ".<key>" : ""),
                          f.unit,
                          f.meaning,
                          g.section,
                          g.scope,
                          f.map,
                          f.absent_when_zero};
          const bool fresh =
              r.index.emplace(std::pair(spec.scope, spec.path), r.specs.size()).second;
          CheckOrDie(fresh, "metrics::MetricRegistry", "a metric is declared twice");
          r.specs.push_back(std::move(spec));
        }
      }
    }
    return r;
  }();
  return registry;
}

// The units of registry.def, indexed by MetricUnit.
struct UnitInfo {
  MetricUnit unit;
  const char* name;
  double steps;
};
const UnitInfo& UnitOf(MetricUnit unit) {
  static const UnitInfo kUnits[] = {
#define METRIC_UNIT(u, name, steps) {MetricUnit::u, name, steps},
#include "harness/metrics/registry.def"
  };
  const auto index = static_cast<std::size_t>(unit);
  CheckOrDie(index < std::size(kUnits) && kUnits[index].unit == unit, "metrics::MetricUnitName",
             "registry.def's units are not in MetricUnit's order");
  return kUnits[index];
}

// "1e-6" for 1e6 steps per unit, "1" for counts.
std::string StepText(MetricUnit unit) {
  const double steps = StepsPerUnit(unit);
  if (steps == 1.0) return "1";
  return "1e-" + std::to_string(static_cast<int>(std::lround(std::log10(steps))));
}

}  // namespace

std::string_view MetricUnitName(MetricUnit unit) { return UnitOf(unit).name; }

double StepsPerUnit(MetricUnit unit) { return UnitOf(unit).steps; }

const std::vector<MetricSpec>& MetricRegistry() { return TheRegistry().specs; }

namespace {
// `nis.<name>.<field>` of a pipeline's own measurement type as the same field of the first
// shipped landmark type (all types' NIS fields are declared alike), or nothing.
std::optional<std::string> SharedNisPath(std::string_view path) {
  constexpr std::string_view kNis = "nis.";
  if (path.substr(0, kNis.size()) != kNis) return std::nullopt;
  const std::size_t dot = path.find('.', kNis.size());
  if (dot == std::string_view::npos) return std::nullopt;
  const std::string name(path.substr(kNis.size(), dot - kNis.size()));
  if (!slam::IsMeasurementTypeName(name)) return std::nullopt;
  return std::string(kNis) + slam::LandmarkTypeName(metrics::kAllTypes[0]) +
         std::string(path.substr(dot));
}
}  // namespace

const MetricSpec* FindMetric(MetricScope scope, std::string_view path) {
  const Registry& r = TheRegistry();
  auto it = r.index.find({scope, std::string(path)});
  if (it == r.index.end() && scope == MetricScope::kPipeline) {
    if (const std::optional<std::string> shared = SharedNisPath(path)) {
      it = r.index.find({scope, *shared});
    }
  }
  return it == r.index.end() ? nullptr : &r.specs[it->second];
}

bool IsKnownMetric(const std::vector<std::string>& names, const std::string& metric) {
  if (std::find(names.begin(), names.end(), metric) != names.end()) return true;
  const std::optional<std::string> shared = SharedNisPath(metric);
  return shared && std::find(names.begin(), names.end(), *shared) != names.end();
}

// ---- MetricWriter -------------------------------------------------------------------------------

MetricWriter::MetricWriter(Json& root, MetricScope scope, std::string prefix)
    : root_(&root), scope_(scope), prefix_(std::move(prefix)) {}

MetricWriter MetricWriter::Sub(std::string_view name) const {
  return MetricWriter(*root_, scope_, prefix_ + std::string(name) + ".");
}

const MetricSpec& MetricWriter::Spec(const std::string& path) const {
  const MetricSpec* spec = FindMetric(scope_, path);
  if (spec == nullptr) {
    const std::string what = "undeclared metric '" + path + "'";
    CheckOrDie(false, "metrics::MetricWriter", what.c_str());
  }
  return *spec;
}

// The JSON node at `path` under the root, objects created on the way (in insertion order).
Json& MetricWriter::Slot(const std::string& path) const {
  Json* node = root_;
  std::size_t begin = 0;
  while (true) {
    const auto dot = path.find('.', begin);
    node = &(*node)[path.substr(begin, dot - begin)];
    if (dot == std::string::npos) return *node;
    begin = dot + 1;
  }
}

void MetricWriter::Set(std::string_view name, double value) const {
  const std::string path = prefix_ + std::string(name);
  const MetricSpec& spec = Spec(path);
  CheckOrDie(spec.unit != MetricUnit::kCount && !spec.map, "metrics::MetricWriter::Set",
             "a count or a map written as a value");
  Slot(path) = RoundToStep(value, StepsPerUnit(spec.unit));
}

void MetricWriter::Set(std::string_view name, const std::optional<double>& value) const {
  if (value) {
    Set(name, *value);
  } else {
    Null(name);
  }
}

void MetricWriter::Count(std::string_view name, std::size_t count) const {
  const std::string path = prefix_ + std::string(name);
  const MetricSpec& spec = Spec(path);
  CheckOrDie(spec.unit == MetricUnit::kCount && !spec.map, "metrics::MetricWriter::Count",
             "a value written as a count");
  if (spec.absent_when_zero && count == 0) return;
  Slot(path) = count;
}

void MetricWriter::Fraction(std::string_view name, std::size_t numerator,
                            std::size_t denominator) const {
  if (denominator == 0) {
    Null(name);
  } else {
    Set(name, static_cast<double>(numerator) / static_cast<double>(denominator));
  }
}

void MetricWriter::Null(std::string_view name) const {
  const std::string path = prefix_ + std::string(name);
  Spec(path);
  Slot(path) = nullptr;
}

void MetricWriter::Map(std::string_view name) const {
  const std::string path = prefix_ + std::string(name);
  Spec(path + ".*");
  Json& slot = Slot(path);
  if (slot.is_null()) slot = Json::object();
}

void MetricWriter::MapValue(std::string_view name, const std::string& key, double value) const {
  const std::string path = prefix_ + std::string(name);
  const MetricSpec& spec = Spec(path + ".*");
  CheckOrDie(spec.unit != MetricUnit::kCount, "metrics::MetricWriter::MapValue",
             "a count written as a value");
  Map(name);
  Slot(path)[key] = RoundToStep(value, StepsPerUnit(spec.unit));
}

void MetricWriter::MapCount(std::string_view name, const std::string& key,
                            std::size_t count) const {
  const std::string path = prefix_ + std::string(name);
  const MetricSpec& spec = Spec(path + ".*");
  CheckOrDie(spec.unit == MetricUnit::kCount, "metrics::MetricWriter::MapCount",
             "a value written as a count");
  Map(name);
  Slot(path)[key] = count;
}

// ---- Docs ---------------------------------------------------------------------------------------

std::vector<std::string> MetricsDocsSections() { return TheRegistry().sections; }

std::string MetricsDocsTable(std::string_view section) {
  std::string table = "| name | unit | step | meaning |\n|---|---|---|---|\n";
  for (const Group& g : Declarations()) {
    if (g.section != section) continue;
    for (const Field& f : g.fields) {
      std::string meaning = f.meaning;
      if (!f.only.empty()) {
        std::string which;
        for (const std::string& v : f.only) which += (which.empty() ? "`" : ", `") + v + "`";
        meaning += " (" + which + " only)";
      }
      if (f.absent_when_zero) meaning += " (absent when 0)";
      table += "| `" + g.prefix + f.name + (f.map ? ".<key>" : "") + "` | " +
               std::string(MetricUnitName(f.unit)) + " | " + StepText(f.unit) + " | " + meaning +
               " |\n";
    }
  }
  return table;
}

std::string UpdateMetricsDocs(const std::string& markdown) {
  std::string out = markdown;
  const std::vector<std::string> sections = MetricsDocsSections();
  for (const std::string& section : sections) {
    const std::string begin = "<!-- BEGIN metrics-table " + section + " -->\n";
    const std::string end = "<!-- END metrics-table " + section + " -->";
    const auto b = out.find(begin);
    const auto e = out.find(end);
    if (b == std::string::npos || e == std::string::npos || e < b) {
      throw std::runtime_error("docs/metrics.md: no block '" + begin.substr(0, begin.size() - 1) +
                               "' ... '" + end + "'");
    }
    out.replace(b + begin.size(), e - (b + begin.size()), MetricsDocsTable(section));
  }
  // Every block names a section of the registry.
  std::size_t at = 0;
  while ((at = out.find("<!-- BEGIN metrics-table ", at)) != std::string::npos) {
    const auto name_begin = at + std::string("<!-- BEGIN metrics-table ").size();
    const auto name_end = out.find(" -->", name_begin);
    const std::string name = out.substr(name_begin, name_end - name_begin);
    if (std::find(sections.begin(), sections.end(), name) == sections.end()) {
      throw std::runtime_error("docs/metrics.md: block for unknown section '" + name + "'");
    }
    at = name_end;
  }
  return out;
}

}  // namespace metrics

std::vector<std::string> MetricNames() {
  std::vector<std::string> names;
  for (const metrics::MetricSpec& spec : metrics::MetricRegistry()) {
    if (spec.scope == metrics::MetricScope::kPipeline && !spec.map) names.push_back(spec.path);
  }
  return names;
}

std::vector<std::string> EvaluationMetricNames() {
  std::vector<std::string> names;
  for (const metrics::MetricSpec& spec : metrics::MetricRegistry()) {
    const bool shared = spec.scope == metrics::MetricScope::kPipeline &&
                        (spec.section == "trajectory" || spec.section == "nees" ||
                         (spec.section == "map" && spec.path.rfind("map.occupancy.", 0) != 0 &&
                          spec.path.rfind("map.area.", 0) != 0));
    if ((shared || spec.scope == metrics::MetricScope::kEvaluation) && !spec.map) {
      names.push_back(spec.path);
    }
  }
  return names;
}

}  // namespace corridorsim
