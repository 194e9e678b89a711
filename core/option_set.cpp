#include "core/option_set.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/error.h"

namespace hos {

namespace {

// The text without the '+' that YAML and people allow before a number
// (from_chars does not); "+-1" stays as it is, and is refused.
std::string_view unsigned_plus(const std::string& text) {
  const std::string_view view(text);
  if (view.size() >= 2 && view[0] == '+' && (std::isdigit(static_cast<unsigned char>(view[1])) || view[1] == '.')) {
    return view.substr(1);
  }
  return view;
}

}  // namespace

template <typename T>
std::optional<T> parse_number(const std::string& text) {
  const std::string_view digits = unsigned_plus(text);
  T value{};
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}
template std::optional<int> parse_number<int>(const std::string&);
template std::optional<double> parse_number<double>(const std::string&);
template std::optional<float> parse_number<float>(const std::string&);
template std::optional<std::size_t> parse_number<std::size_t>(const std::string&);
template std::optional<std::uint32_t> parse_number<std::uint32_t>(const std::string&);

template <typename T>
std::string number_problem(const std::string& text) {
  const std::string_view digits = unsigned_plus(text);
  long double wide = 0;  // holds what T cannot: tells underflow from overflow
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, wide);
  if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range)) return "is not a number";
  if (ec == std::errc::result_out_of_range) {
    // Beyond even long double ("1e-99999"): the exponent's sign tells which way.
    const auto e = digits.find_first_of("eE");
    wide = e != std::string_view::npos && e + 1 < digits.size() && digits[e + 1] == '-'
               ? std::numeric_limits<long double>::denorm_min()
               : std::numeric_limits<long double>::max();
  }
  if constexpr (std::is_integral_v<T>) {
    if (wide != std::trunc(wide)) return "is not an integer";
    if (wide < 0 && std::is_unsigned_v<T>) return "is negative (a count or a seed)";
    if (wide >= std::numeric_limits<T>::min() && wide <= std::numeric_limits<T>::max()) {
      return "is not written as an integer (no decimal point or exponent)";
    }
    return "is too large in magnitude for an integer (the largest is " + print_number(std::numeric_limits<T>::max()) +
           ")";
  }
  if (std::fabs(wide) < 1) {
    return "underflows: it is nonzero but smaller in magnitude than the smallest number it can be stored as (" +
           print_number(std::numeric_limits<T>::denorm_min()) + "); write 0 for zero";
  }
  return "overflows: it is larger in magnitude than the largest number it can be stored as (" +
         print_number(std::numeric_limits<T>::max()) + ")";
}
template std::string number_problem<int>(const std::string&);
template std::string number_problem<double>(const std::string&);
template std::string number_problem<float>(const std::string&);
template std::string number_problem<std::size_t>(const std::string&);
template std::string number_problem<std::uint32_t>(const std::string&);

template <typename T>
std::string print_number(T value) {
  std::ostringstream s;
  s << value;
  return s.str();
}
template std::string print_number<int>(int);
template std::string print_number<double>(double);
template std::string print_number<float>(float);
template std::string print_number<std::size_t>(std::size_t);
template std::string print_number<std::uint32_t>(std::uint32_t);

namespace {

void flatten(const YAML::Node& node, const std::string& prefix, std::vector<std::pair<std::string, YAML::Node>>& out) {
  for (const auto& item : node) {
    const std::string key = prefix.empty() ? item.first.Scalar() : prefix + "." + item.first.Scalar();
    if (item.second.IsMap()) {
      flatten(item.second, key, out);
    } else {
      out.emplace_back(key, item.second);
    }
  }
}

}  // namespace

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

OptionSet::OptionSet(std::string section) : section_(std::move(section)) {}

void OptionSet::add_entry(Entry entry) {
  if (find(entry.key)) throw std::logic_error("option " + entry.key + " registered twice");
  entries_.push_back(std::move(entry));
}

const OptionSet::Entry* OptionSet::find(const std::string& key) const {
  for (const auto& e : entries_) {
    if (e.key == key) return &e;
  }
  return nullptr;
}

bool OptionSet::has_key(const std::string& key) const { return find(key) != nullptr; }

void OptionSet::add(const std::string& key, bool& value, std::string doc) {
  add_entry({key, std::move(doc), "true or false",
             [&value](const std::string& t) {
               if (t == "true" || t == "yes" || t == "on" || t == "1") {
                 value = true;
               } else if (t == "false" || t == "no" || t == "off" || t == "0") {
                 value = false;
               } else {
                 throw std::invalid_argument("must be true or false");
               }
             },
             [&value]() { return std::string(value ? "true" : "false"); }, nullptr});  // every bool is allowed
}

void OptionSet::add_odd(const std::string& key, int& value, std::string doc, int min, int max) {
  auto odd_in_range = [min, max](int v) { return v % 2 != 0 && v >= min && v <= max; };
  add_number(key, value, std::move(doc), "an odd integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]",
             odd_in_range);
}

void OptionSet::add(const std::string& key, std::string& value, std::string doc) {
  add_entry({key, std::move(doc), "a string", [&value](const std::string& t) { value = t; },
             [&value]() { return value; }, nullptr});  // every string is allowed
}

void OptionSet::add_choice(const std::string& key,
                           std::string& value,
                           const std::vector<std::string>& choices,
                           std::string doc) {
  std::string allowed = "one of:";
  for (const auto& c : choices) allowed += " " + c;
  add_entry({key, std::move(doc), allowed,
             [&value, choices, allowed](const std::string& t) {
               if (std::find(choices.begin(), choices.end(), t) == choices.end()) {
                 throw std::invalid_argument("must be " + allowed);
               }
               value = t;
             },
             [&value]() { return value; },
             [&value, choices, allowed]() {
               if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
                 throw std::invalid_argument("must be " + allowed);
               }
             }});
}

void OptionSet::check_values() const {
  for (const auto& e : entries_) {
    if (!e.check) continue;
    try {
      e.check();
    } catch (const std::invalid_argument& error) {
      throw ConfigError(section_ + "." + e.key, "value " + e.print() + " " + error.what());
    }
  }
}

void OptionSet::add_flag(std::string flag, const std::string& key, std::string fixed_value) {
  if (!find(key)) throw std::logic_error("flag " + flag + " for unregistered option " + key);
  flags_.push_back({std::move(flag), key, std::move(fixed_value)});
}

std::string OptionSet::documentation(const std::string& key) const {
  const Entry* entry = find(key);
  if (!entry) throw std::logic_error("no option " + key);
  return entry->doc + " [" + entry->allowed + "]";
}

std::string OptionSet::closest_key(const std::string& key) const {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const auto& e : entries_) {
    const std::size_t d = edit_distance(key, e.key);
    if (d < best_distance) {
      best_distance = d;
      best = e.key;
    }
  }
  return best;
}

void OptionSet::apply_assignment(const std::string& key, const std::string& value, const std::string& source) {
  const Entry* entry = find(key);
  const std::string full_key = section_ + "." + key;
  if (!entry) {
    std::string reason = "unknown option (in " + source + ")";
    const std::string closest = closest_key(key);
    if (!closest.empty()) reason += "; did you mean " + section_ + "." + closest + "?";
    throw ConfigError(full_key, reason);
  }
  try {
    entry->parse(value);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(full_key, "value '" + value + "' (in " + source + ") " + e.what());
  }
}

void OptionSet::apply_yaml(const YAML::Node& node, const std::string& source) {
  if (!node || node.IsNull()) return;
  if (!node.IsMap()) {
    throw ConfigError(
        section_, "must be a map of options (in " + source + ", line " + std::to_string(node.Mark().line + 1) + ")");
  }
  std::vector<std::pair<std::string, YAML::Node>> flat;
  flatten(node, "", flat);
  for (const auto& [key, value] : flat) {
    const std::string where = source + ", line " + std::to_string(value.Mark().line + 1);
    if (!value.IsScalar()) {
      throw ConfigError(section_ + "." + key, "must be a single value (in " + where + ")");
    }
    apply_assignment(key, value.Scalar(), where);
  }
}

YAML::Node OptionSet::to_yaml() const {
  YAML::Node root(YAML::NodeType::Map);
  for (const auto& e : entries_) {
    // Walk the dotted key, creating nested maps.
    std::vector<std::string> parts;
    std::stringstream ss(e.key);
    for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
    std::vector<YAML::Node> chain{root};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      YAML::Node child = chain.back()[parts[i]];
      if (!child.IsMap()) child = YAML::Node(YAML::NodeType::Map);
      chain.back()[parts[i]] = child;
      chain.push_back(chain.back()[parts[i]]);
    }
    chain.back()[parts.back()] = YAML::Load(e.print());
  }
  return root;
}

std::string OptionSet::documented_yaml() const {
  std::ostringstream s;
  s << section_ << ":\n";
  for (const auto& e : entries_) {
    s << "  " << e.key << ": " << e.print() << "  # " << e.doc << " [" << e.allowed << "]\n";
  }
  return s.str();
}

std::vector<std::string> OptionSet::keys() const {
  std::vector<std::string> out;
  for (const auto& e : entries_) out.push_back(e.key);
  return out;
}

namespace {

// Aliases let a few hundred bytes of YAML stand for billions of values (an
// alias of a list of aliases multiplies them), which every walk over the
// config would then visit. A config holds a few hundred options, so one that
// reaches more values than this is refused before anything walks it fully.
constexpr std::size_t kMaxConfigValues = 10000;

void check_value_count(const YAML::Node& root, const std::string& path) {
  std::size_t visited = 0;
  std::vector<YAML::Node> pending{root};
  while (!pending.empty()) {
    const YAML::Node node = pending.back();
    pending.pop_back();
    if (++visited > kMaxConfigValues) {
      throw ConfigError(path, "holds more than " + std::to_string(kMaxConfigValues) +
                                  " values once its aliases (*name) are expanded; a config needs a few hundred at "
                                  "most (are aliases nested in lists of aliases?)");
    }
    for (const auto& item : node) {
      if (node.IsMap()) {
        pending.push_back(item.first);
        pending.push_back(item.second);
      } else {
        pending.push_back(item);
      }
    }
  }
}

// A key given twice in one map would silently lose one of its values.
void check_unique_keys(const YAML::Node& node, const std::string& path) {
  if (node.IsSequence()) {
    for (const auto& item : node) check_unique_keys(item, path);
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> first_line;
  for (const auto& item : node) {
    const int line = item.first.Mark().line + 1;
    const auto [it, inserted] = first_line.emplace(item.first.Scalar(), line);
    if (!inserted) {
      throw ConfigError(item.first.Scalar(), "is given twice (in " + path + ", lines " + std::to_string(it->second) +
                                                 " and " + std::to_string(line) + ")");
    }
    check_unique_keys(item.second, path);
  }
}

}  // namespace

YAML::Node load_yaml_file(const std::string& path) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAllFromFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path, "cannot open config file");
  } catch (const YAML::Exception& e) {
    // A configuration error like an unknown key (exit 2), not unreadable input.
    throw ConfigError(path, "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  // Options in a second document would be ignored without a word; an empty
  // one (a trailing "---") loses nothing.
  for (std::size_t i = 1; i < documents.size(); ++i) {
    if (documents[i].IsNull()) continue;
    throw ConfigError(path, "holds a second YAML document (after a \"---\" line, at line " +
                                std::to_string(documents[i].Mark().line + 1) +
                                "), which would be ignored; a config is one document: merge them");
  }
  const YAML::Node root = documents.empty() ? YAML::Node() : documents.front();
  check_value_count(root, path);
  check_unique_keys(root, path);
  return root;
}

}  // namespace hos
