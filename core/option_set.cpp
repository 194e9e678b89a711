#include "core/option_set.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/error.h"

namespace hos {

template <typename T>
std::optional<T> parse_number(const std::string& text) {
  T value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}
template std::optional<int> parse_number<int>(const std::string&);
template std::optional<double> parse_number<double>(const std::string&);
template std::optional<float> parse_number<float>(const std::string&);

template <typename T>
std::string print_number(T value) {
  std::ostringstream s;
  s << value;
  return s.str();
}
template std::string print_number<int>(int);
template std::string print_number<double>(double);
template std::string print_number<float>(float);

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
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path, "cannot open config file");
  } catch (const YAML::Exception& e) {
    // A configuration error like an unknown key (exit 2), not unreadable input.
    throw ConfigError(path, "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  check_unique_keys(root, path);
  return root;
}

}  // namespace hos
