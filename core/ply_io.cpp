#include "core/ply_io.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/huge_pages.h"

namespace hos {
namespace fs = std::filesystem;
namespace {

enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

struct TypeName {
  const char* name;
  PlyType type;
};
constexpr TypeName kTypeNames[] = {
    {"char", PlyType::kInt8},       {"int8", PlyType::kInt8},       {"uchar", PlyType::kUInt8},
    {"uint8", PlyType::kUInt8},     {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
    {"ushort", PlyType::kUInt16},   {"uint16", PlyType::kUInt16},   {"int", PlyType::kInt32},
    {"int32", PlyType::kInt32},     {"uint", PlyType::kUInt32},     {"uint32", PlyType::kUInt32},
    {"float", PlyType::kFloat32},   {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
    {"float64", PlyType::kFloat64},
};

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUInt8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;

  int find(std::initializer_list<const char*> names) const {
    for (const char* n : names) {
      for (std::size_t i = 0; i < properties.size(); ++i) {
        if (properties[i].name == n) return static_cast<int>(i);
      }
    }
    return -1;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;
};

// One header line's words with its error context.
class HeaderLine {
 public:
  HeaderLine(const std::string& file, int number, const std::string& text) : file_(file), number_(number), s_(text) {}
  std::istringstream& words() { return s_; }
  InputError bad(const std::string& reason) const {
    return InputError(file_, "PLY header line " + std::to_string(number_) + ": " + reason);
  }
  PlyType type_named(const std::string& name) const {
    for (const auto& t : kTypeNames) {
      if (name == t.name) return t.type;
    }
    throw bad("unknown property type '" + name + "'");
  }

 private:
  const std::string& file_;
  int number_;
  std::istringstream s_;
};

PlyFormat parse_format(HeaderLine& line) {
  std::string format, version;
  line.words() >> format >> version;
  if (format == "ascii") return PlyFormat::kAscii;
  if (format == "binary_little_endian") return PlyFormat::kBinaryLittleEndian;
  if (format == "binary_big_endian") return PlyFormat::kBinaryBigEndian;
  throw line.bad("unknown format '" + format + "'");
}

void add_element(HeaderLine& line, PlyHeader& header) {
  PlyElement element;
  long long count = -1;
  if (!(line.words() >> element.name >> count) || count < 0) throw line.bad("malformed element line");
  for (const PlyElement& other : header.elements) {
    if (other.name == element.name) throw line.bad("element '" + element.name + "' appears twice");
  }
  element.count = static_cast<std::size_t>(count);
  header.elements.push_back(std::move(element));
}

void add_property(HeaderLine& line, PlyHeader& header) {
  if (header.elements.empty()) throw line.bad("property before any element");
  PlyProperty property;
  std::string type;
  std::istringstream& s = line.words();
  if (!(s >> type)) throw line.bad("malformed property line");
  if (type == "list") {
    std::string count_type, item_type;
    if (!(s >> count_type >> item_type >> property.name)) throw line.bad("malformed list property");
    property.is_list = true;
    property.count_type = line.type_named(count_type);
    property.type = line.type_named(item_type);
  } else {
    property.type = line.type_named(type);
    if (!(s >> property.name)) throw line.bad("property without a name");
  }
  // A repeated name would fill one attribute twice (and leave its length
  // inconsistent): the file cannot be read unambiguously.
  PlyElement& element = header.elements.back();
  for (const PlyProperty& other : element.properties) {
    if (other.name == property.name) {
      throw line.bad("property '" + property.name + "' appears twice in element '" + element.name + "'");
    }
  }
  element.properties.push_back(property);
}

PlyHeader parse_header(const std::string& file, std::string_view data) {
  if (data.compare(0, 3, "ply") != 0 || (data.size() > 3 && data[3] != '\n' && data[3] != '\r')) {
    throw InputError(file, "not a PLY file (missing 'ply' magic line)");
  }
  PlyHeader header;
  bool have_format = false;
  std::size_t pos = 0;
  for (int line_number = 1;; ++line_number) {
    const auto end = data.find('\n', pos);
    if (end == std::string::npos) {
      throw InputError(file, "PLY header is truncated (no 'end_header' line)");
    }
    std::string text(data.substr(pos, end - pos));
    pos = end + 1;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    HeaderLine line(file, line_number, text);
    std::string keyword;
    line.words() >> keyword;
    if (line_number == 1 || keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      header.format = parse_format(line);
      have_format = true;
    } else if (keyword == "element") {
      add_element(line, header);
    } else if (keyword == "property") {
      add_property(line, header);
    } else {
      throw line.bad("unknown keyword '" + keyword + "'");
    }
  }
  if (!have_format) throw InputError(file, "PLY header has no 'format' line");
  header.data_offset = pos;
  return header;
}

// Sequential reader of the body: ASCII tokens or binary values of either
// endianness, with truncation checks.
class BodyReader {
 public:
  BodyReader(const std::string& file, std::string_view data, const PlyHeader& header)
      : file_(file), data_(data), pos_(header.data_offset), format_(header.format) {}

  double read(PlyType type) {
    if (format_ == PlyFormat::kAscii) return read_ascii();
    const std::size_t n = type_size(type);
    if (data_.size() - pos_ < n) truncated();
    unsigned char bytes[8];
    std::memcpy(bytes, data_.data() + pos_, n);
    pos_ += n;
    const bool file_little = format_ == PlyFormat::kBinaryLittleEndian;
    if (file_little != (std::endian::native == std::endian::little)) std::reverse(bytes, bytes + n);
    return decode(type, bytes);
  }

  static double decode(PlyType type, const unsigned char* bytes) {
    switch (type) {
      case PlyType::kInt8:
        return static_cast<double>(load<std::int8_t>(bytes));
      case PlyType::kUInt8:
        return static_cast<double>(load<std::uint8_t>(bytes));
      case PlyType::kInt16:
        return static_cast<double>(load<std::int16_t>(bytes));
      case PlyType::kUInt16:
        return static_cast<double>(load<std::uint16_t>(bytes));
      case PlyType::kInt32:
        return static_cast<double>(load<std::int32_t>(bytes));
      case PlyType::kUInt32:
        return static_cast<double>(load<std::uint32_t>(bytes));
      case PlyType::kFloat32:
        return static_cast<double>(load<float>(bytes));
      case PlyType::kFloat64:
        return load<double>(bytes);
    }
    return 0.0;
  }

  void set_context(const std::string& element, std::size_t row) {
    element_ = &element;
    row_ = row;
  }

  bool binary() const { return format_ != PlyFormat::kAscii; }

  std::size_t remaining() const { return data_.size() - pos_; }

  bool swap_bytes() const {
    return (format_ == PlyFormat::kBinaryLittleEndian) != (std::endian::native == std::endian::little);
  }

  // The next `count` fixed-size binary rows, bounds-checked once for the
  // whole element (the hot path of large point clouds).
  const unsigned char* take_rows(std::size_t count, std::size_t row_bytes) {
    const std::size_t available = data_.size() - pos_;
    if (row_bytes > 0 && available / row_bytes < count) {
      row_ = available / row_bytes;
      truncated();
    }
    const auto* rows = reinterpret_cast<const unsigned char*>(data_.data()) + pos_;
    pos_ += count * row_bytes;
    return rows;
  }

  // One row of scalar properties at `p`, decoded into `out` in header order.
  static void decode_row(const std::vector<PlyProperty>& properties, bool swap, const unsigned char* p, double* out) {
    for (std::size_t k = 0; k < properties.size(); ++k) {
      const std::size_t n = type_size(properties[k].type);
      unsigned char bytes[8];
      std::memcpy(bytes, p, n);
      if (swap) std::reverse(bytes, bytes + n);
      out[k] = decode(properties[k].type, bytes);
      p += n;
    }
  }

  void expect_end() {
    if (format_ == PlyFormat::kAscii) {
      skip_space();
      if (pos_ < data_.size()) {
        throw InputError(file_, "more data than the header's element counts declare");
      }
    } else if (pos_ != data_.size()) {
      throw InputError(file_, std::to_string(data_.size() - pos_) +
                                  " bytes after the last element: the data does not match the "
                                  "header's counts");
    }
  }

 private:
  template <typename T>
  static T load(const unsigned char* bytes) {
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return v;
  }

  void skip_space() {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
  }

  double read_ascii() {
    skip_space();
    if (pos_ >= data_.size()) truncated();
    const char* begin = data_.data() + pos_;
    const char* end = data_.data() + data_.size();
    double value = 0.0;
    auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec != std::errc() && ec != std::errc::result_out_of_range) {
      // from_chars does not parse "nan"/"inf" spellings with signs everywhere; fall back.
      const char* token_end = begin;
      while (token_end < end && !std::isspace(static_cast<unsigned char>(*token_end))) ++token_end;
      const std::string token(begin, token_end);
      char* parsed_end = nullptr;
      value = std::strtod(token.c_str(), &parsed_end);
      if (parsed_end != token.c_str() + token.size()) {
        throw InputError(
            file_, "element '" + *element_ + "' row " + std::to_string(row_) + ": '" + token + "' is not a number");
      }
      ptr = token_end;
    }
    pos_ = static_cast<std::size_t>(ptr - data_.data());
    return value;
  }

  [[noreturn]] void truncated() const {
    throw InputError(file_, "data ends in element '" + *element_ + "' row " + std::to_string(row_) +
                                ": the file is truncated or the header's counts are wrong");
  }

  const std::string& file_;
  std::string_view data_;
  std::size_t pos_;
  PlyFormat format_;
  const std::string* element_ = &kNoElement;
  std::size_t row_ = 0;
  static inline const std::string kNoElement = "(header)";
};

// The file mapped read-only into memory: no copy and no zero-fill of a
// buffer, so a large binary file costs little more than the page cache reads.
class MappedFile {
 public:
  explicit MappedFile(const fs::path& path) {
    if (!fs::exists(path)) throw InputError(path.string(), "file does not exist");
    fd_ = ::open(path.c_str(), O_RDONLY);
    if (fd_ < 0) throw InputError(path.string(), "cannot open file");
    struct stat st {};
    if (::fstat(fd_, &st) != 0) {
      ::close(fd_);
      throw InputError(path.string(), "cannot read the file's size");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      // MAP_POPULATE reads the pages in one go instead of one fault per page.
      void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd_, 0);
      if (p == MAP_FAILED) {
        ::close(fd_);
        throw InputError(path.string(), "cannot map the file into memory");
      }
      data_ = static_cast<const char*>(p);
      ::madvise(p, size_, MADV_SEQUENTIAL);
    }
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
    if (fd_ >= 0) ::close(fd_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view view() const { return {data_ ? data_ : "", size_}; }

 private:
  int fd_ = -1;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

// Property indices of the vertex attributes hos understands.
struct VertexLayout {
  int position[3];
  int normal[3];
  int color[3];
  int confidence;
  std::vector<int> extra;  // other scalar properties
};

VertexLayout vertex_layout(const std::string& file, const PlyElement& vertex) {
  VertexLayout layout{};
  const char* pos_names[3] = {"x", "y", "z"};
  const char* normal_names[3] = {"nx", "ny", "nz"};
  const char* color_names[3][3] = {
      {"red", "r", "diffuse_red"}, {"green", "g", "diffuse_green"}, {"blue", "b", "diffuse_blue"}};
  for (int k = 0; k < 3; ++k) {
    layout.position[k] = vertex.find({pos_names[k]});
    if (layout.position[k] < 0) {
      throw InputError(file, std::string("vertex element has no '") + pos_names[k] + "' property");
    }
    layout.normal[k] = vertex.find({normal_names[k]});
    layout.color[k] = vertex.find({color_names[k][0], color_names[k][1], color_names[k][2]});
  }
  // Normals and colours are used only when all three components are present.
  if (std::min({layout.normal[0], layout.normal[1], layout.normal[2]}) < 0) {
    layout.normal[0] = layout.normal[1] = layout.normal[2] = -1;
  }
  if (std::min({layout.color[0], layout.color[1], layout.color[2]}) < 0) {
    layout.color[0] = layout.color[1] = layout.color[2] = -1;
  }
  layout.confidence = vertex.find({"confidence", "quality", "value"});
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const int idx = static_cast<int>(i);
    const bool used = std::count(layout.position, layout.position + 3, idx) ||
                      std::count(layout.normal, layout.normal + 3, idx) ||
                      std::count(layout.color, layout.color + 3, idx) || layout.confidence == idx;
    if (!used && !vertex.properties[i].is_list) layout.extra.push_back(idx);
  }
  return layout;
}

std::uint8_t to_color_byte(double v, PlyType type) {
  // Float colours are in [0, 1] by convention; integer ones in [0, 255].
  if (type == PlyType::kFloat32 || type == PlyType::kFloat64) v *= 255.0;
  if (!(v >= 0.0)) return 0;
  return static_cast<std::uint8_t>(std::min(255.0, std::round(v)));
}

// Stores decoded vertex rows into pre-sized arrays, one slot per row, so that
// binary rows can be decoded in parallel; rows with non-finite positions are
// flagged and removed afterwards by compact() (dropped and counted, never
// propagated).
class VertexSink {
 public:
  VertexSink(const PlyElement& element, const VertexLayout& layout, PointCloud& cloud)
      : element_(element), layout_(layout), cloud_(cloud), finite_(element.count, 1) {
    const std::size_t n = element.count;
    // Huge pages before the first touch: page faults of the output arrays
    // were the largest cost of reading a big cloud.
    const auto allocate = [n](auto& values) {
      values.reserve(n);
      advise_huge_pages(values);
      values.resize(n);
    };
    allocate(cloud.positions);
    if (layout.normal[0] >= 0) allocate(cloud.normals);
    if (layout.color[0] >= 0) allocate(cloud.colors);
    if (layout.confidence >= 0) allocate(cloud.confidence);
    for (int idx : layout.extra) {
      auto& column = cloud.scalars[element.properties[idx].name];
      allocate(column);
      extra_columns_.push_back(&column);
    }
  }

  // `row` holds the element's property values in header order.
  void store(std::size_t slot, const double* row) {
    const Eigen::Vector3f x(row[layout_.position[0]], row[layout_.position[1]], row[layout_.position[2]]);
    cloud_.positions[slot] = x;
    if (!x.allFinite()) finite_[slot] = 0;
    if (layout_.normal[0] >= 0) {
      Eigen::Vector3f n(row[layout_.normal[0]], row[layout_.normal[1]], row[layout_.normal[2]]);
      if (!n.allFinite()) n.setZero();  // an unusable normal, not an unusable point
      cloud_.normals[slot] = n;
    }
    if (layout_.color[0] >= 0) {
      Rgb8& c = cloud_.colors[slot];
      for (int k = 0; k < 3; ++k) {
        c[k] = to_color_byte(row[layout_.color[k]], element_.properties[layout_.color[k]].type);
      }
    }
    if (layout_.confidence >= 0) {
      const double c = row[layout_.confidence];
      cloud_.confidence[slot] = static_cast<float>(c);  // checked by count_invalid_confidence
    }
    for (std::size_t e = 0; e < layout_.extra.size(); ++e) {
      (*extra_columns_[e])[slot] = static_cast<float>(row[layout_.extra[e]]);
    }
  }

  // Removes the flagged rows, keeping order; returns how many were removed.
  std::size_t compact() {
    const std::size_t removed = static_cast<std::size_t>(std::count(finite_.begin(), finite_.end(), 0));
    if (removed == 0) return 0;
    compact_array(cloud_.positions);
    compact_array(cloud_.normals);
    compact_array(cloud_.colors);
    compact_array(cloud_.confidence);
    for (auto* column : extra_columns_) compact_array(*column);
    return removed;
  }

 private:
  template <typename T>
  void compact_array(std::vector<T>& values) const {
    if (values.empty()) return;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (finite_[i]) values[kept++] = values[i];
    }
    values.resize(kept);
  }

  const PlyElement& element_;
  const VertexLayout& layout_;
  PointCloud& cloud_;
  std::vector<std::vector<float>*> extra_columns_;
  std::vector<std::uint8_t> finite_;
};

struct ParsedPly {
  PointCloud vertices;
  std::vector<Eigen::Vector3i> faces;
  std::size_t num_nonfinite = 0;
  std::size_t num_invalid_confidence = 0;
};

// A confidence is a weight: NaN, infinite or negative ones become 0 (the
// point then weighs nothing) and are counted for the reader's report.
std::size_t zero_invalid_confidence(std::vector<float>& confidence) {
  std::size_t invalid = 0;
  for (float& c : confidence) {
    if (!(c >= 0.0f) || !std::isfinite(c)) {
      c = 0.0f;
      ++invalid;
    }
  }
  return invalid;
}

// Reads the rows of one element with ASCII tokens or list properties, one value
// at a time. Vertex rows go to `sink`; face lists (when `face_list` >= 0) are
// fan-triangulated into `faces`.
void read_rows_sequentially(BodyReader& body,
                            const std::string& file,
                            const PlyElement& element,
                            VertexSink* sink,
                            int face_list,
                            std::vector<Eigen::Vector3i>& faces) {
  std::vector<double> row(element.properties.size());
  std::vector<int> polygon;
  for (std::size_t r = 0; r < element.count; ++r) {
    body.set_context(element.name, r);
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const auto& prop = element.properties[p];
      if (!prop.is_list) {
        row[p] = body.read(prop.type);
        continue;
      }
      const double count = body.read(prop.count_type);
      if (!(count >= 0) || count > 1e6) {
        throw InputError(file, "element '" + element.name + "' row " + std::to_string(r) + ": invalid list length");
      }
      const bool keep = static_cast<int>(p) == face_list;
      if (keep) polygon.clear();
      for (int i = 0; i < static_cast<int>(count); ++i) {
        const double value = body.read(prop.type);
        if (keep) polygon.push_back(static_cast<int>(value));
      }
    }
    if (sink) {
      sink->store(r, row.data());
    } else if (face_list >= 0 && polygon.size() >= 3) {
      for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
        faces.emplace_back(polygon[0], polygon[i], polygon[i + 1]);
      }
    }
  }
}

ParsedPly parse_ply(const fs::path& path, bool want_faces) {
  const std::string file = path.string();
  const MappedFile mapped(path);
  const std::string_view data = mapped.view();
  const PlyHeader header = parse_header(file, data);
  BodyReader body(file, data, header);
  ParsedPly out;
  bool have_vertex = false;
  for (const auto& element : header.elements) {
    const bool is_vertex = element.name == "vertex";
    // A row takes at least one byte per scalar (binary) or two (a digit and a
    // separator), so a count the data cannot hold is refused before anything
    // is allocated for it.
    const std::size_t min_row_bytes = (body.binary() ? 1 : 2) * std::max<std::size_t>(element.properties.size(), 1);
    if (element.count > body.remaining() / min_row_bytes) {
      throw InputError(file, "the header declares " + std::to_string(element.count) + " rows of element '" +
                                 element.name + "' but only " + std::to_string(body.remaining()) +
                                 " bytes of data remain: the file is truncated or the header's counts are wrong");
    }
    const VertexLayout layout = is_vertex ? vertex_layout(file, element) : VertexLayout{};
    std::optional<VertexSink> sink;
    if (is_vertex) {
      if (have_vertex) throw InputError(file, "PLY file has more than one 'vertex' element");
      have_vertex = true;
      sink.emplace(element, layout, out.vertices);
    }
    int face_list = -1;
    if (element.name == "face" && want_faces) {
      face_list = element.find({"vertex_indices", "vertex_index"});
      if (face_list < 0 || !element.properties[face_list].is_list) {
        throw InputError(file, "face element has no 'vertex_indices' list");
      }
    }
    const bool fixed_rows = body.binary() && std::none_of(element.properties.begin(), element.properties.end(),
                                                          [](const PlyProperty& p) { return p.is_list; });
    if (!fixed_rows) {
      read_rows_sequentially(body, file, element, sink ? &*sink : nullptr, face_list, out.faces);
    } else {
      std::size_t row_bytes = 0;
      for (const auto& p : element.properties) row_bytes += type_size(p.type);
      body.set_context(element.name, 0);
      const unsigned char* rows = body.take_rows(element.count, row_bytes);
      if (sink) {
        // Rows have a fixed size, so they decode independently: in parallel,
        // which also spreads the first touch of the output pages over cores.
        const bool swap = body.swap_bytes();
        const auto count = static_cast<std::ptrdiff_t>(element.count);
#pragma omp parallel
        {
          std::vector<double> row(element.properties.size());
#pragma omp for schedule(static)
          for (std::ptrdiff_t r = 0; r < count; ++r) {
            BodyReader::decode_row(element.properties, swap, rows + r * row_bytes, row.data());
            sink->store(static_cast<std::size_t>(r), row.data());
          }
        }
      }
    }
    if (sink) {
      out.num_nonfinite = sink->compact();
      out.num_invalid_confidence = zero_invalid_confidence(out.vertices.confidence);
    }
  }
  body.expect_end();
  if (!have_vertex) throw InputError(file, "PLY file has no 'vertex' element");
  return out;
}

// ---- writing ---------------------------------------------------------------

class BodyWriter {
 public:
  explicit BodyWriter(PlyFormat format) : format_(format) {}

  template <typename T>
  void write(T value) {
    if (format_ == PlyFormat::kAscii) {
      if (!at_line_start_) out_.push_back(' ');
      at_line_start_ = false;
      if constexpr (std::is_floating_point_v<T>) {
        char buffer[64];
        auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
        out_.append(buffer, ptr);
      } else {
        out_.append(std::to_string(static_cast<long long>(value)));
      }
      return;
    }
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    const bool file_little = format_ == PlyFormat::kBinaryLittleEndian;
    if (file_little != (std::endian::native == std::endian::little)) {
      std::reverse(bytes, bytes + sizeof(T));
    }
    out_.append(reinterpret_cast<const char*>(bytes), sizeof(T));
  }

  void end_row() {
    if (format_ == PlyFormat::kAscii) out_.push_back('\n');
    at_line_start_ = true;
  }

  std::string& data() { return out_; }

 private:
  PlyFormat format_;
  std::string out_;
  bool at_line_start_ = true;
};

const char* format_name(PlyFormat format) {
  switch (format) {
    case PlyFormat::kAscii:
      return "ascii";
    case PlyFormat::kBinaryLittleEndian:
      return "binary_little_endian";
    case PlyFormat::kBinaryBigEndian:
      return "binary_big_endian";
  }
  return "ascii";
}

struct VertexArrays {
  const std::vector<Eigen::Vector3f>* positions;
  const std::vector<Eigen::Vector3f>* normals;
  const std::vector<Rgb8>* colors;
  const std::vector<float>* confidence;
  const std::map<std::string, std::vector<float>>* scalars;
};

std::string vertex_header(const VertexArrays& v) {
  std::string h = "element vertex " + std::to_string(v.positions->size()) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (!v.normals->empty()) h += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!v.colors->empty()) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (v.confidence && !v.confidence->empty()) h += "property float confidence\n";
  for (const auto& [name, values] : *v.scalars) h += "property float " + name + "\n";
  return h;
}

void write_vertices(BodyWriter& out, const VertexArrays& v) {
  for (std::size_t i = 0; i < v.positions->size(); ++i) {
    for (int k = 0; k < 3; ++k) out.write((*v.positions)[i][k]);
    if (!v.normals->empty()) {
      for (int k = 0; k < 3; ++k) out.write((*v.normals)[i][k]);
    }
    if (!v.colors->empty()) {
      for (int k = 0; k < 3; ++k) out.write((*v.colors)[i][k]);
    }
    if (v.confidence && !v.confidence->empty()) out.write((*v.confidence)[i]);
    for (const auto& [name, values] : *v.scalars) out.write(values[i]);
    out.end_row();
  }
}

void write_ply_file(const fs::path& path, const std::string& header, std::string& body) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw OutputError(path.string(), "the file cannot be created");
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
    if (!out) throw OutputError(path.string(), "write failed (disk full?)");
  });
}

std::string header_start(PlyFormat format) {
  return std::string("ply\nformat ") + format_name(format) + " 1.0\ncomment written by hos\n";
}

}  // namespace

PointCloud read_point_cloud_ply(const fs::path& path, PlyReadReport* report) {
  ParsedPly parsed = parse_ply(path, /*want_faces=*/false);
  if (report) {
    report->num_skipped_nonfinite = parsed.num_nonfinite;
    report->num_invalid_confidence = parsed.num_invalid_confidence;
  }
  return std::move(parsed.vertices);
}

TriangleMesh read_mesh_ply(const fs::path& path) {
  ParsedPly parsed = parse_ply(path, /*want_faces=*/true);
  if (parsed.num_nonfinite > 0) {
    throw InputError(path.string(), std::to_string(parsed.num_nonfinite) + " vertices have non-finite coordinates");
  }
  TriangleMesh mesh;
  mesh.vertices = std::move(parsed.vertices.positions);
  mesh.normals = std::move(parsed.vertices.normals);
  mesh.colors = std::move(parsed.vertices.colors);
  mesh.vertex_scalars = std::move(parsed.vertices.scalars);
  if (!parsed.vertices.confidence.empty()) {
    mesh.vertex_scalars["quality"] = std::move(parsed.vertices.confidence);
  }
  const int n = static_cast<int>(mesh.vertices.size());
  for (const auto& f : parsed.faces) {
    if ((f.array() < 0).any() || (f.array() >= n).any()) {
      throw InputError(path.string(), "a face refers to a vertex index outside [0, " + std::to_string(n) + ")");
    }
  }
  mesh.faces = std::move(parsed.faces);
  return mesh;
}

void write_point_cloud_ply(const fs::path& path, const PointCloud& cloud, PlyFormat format) {
  cloud.check_consistent();
  const VertexArrays v{&cloud.positions, &cloud.normals, &cloud.colors, &cloud.confidence, &cloud.scalars};
  const std::string header = header_start(format) + vertex_header(v) + "end_header\n";
  BodyWriter body(format);
  write_vertices(body, v);
  write_ply_file(path, header, body.data());
}

void write_mesh_ply(const fs::path& path, const TriangleMesh& mesh, PlyFormat format) {
  mesh.check_consistent();
  const VertexArrays v{&mesh.vertices, &mesh.normals, &mesh.colors, nullptr, &mesh.vertex_scalars};
  const std::string header = header_start(format) + vertex_header(v) + "element face " +
                             std::to_string(mesh.faces.size()) +
                             "\nproperty list uchar int vertex_indices\nend_header\n";
  BodyWriter body(format);
  write_vertices(body, v);
  for (const auto& f : mesh.faces) {
    body.write(std::uint8_t{3});
    for (int k = 0; k < 3; ++k) body.write(static_cast<std::int32_t>(f[k]));
    body.end_row();
  }
  write_ply_file(path, header, body.data());
}

}  // namespace hos
