#include "cases/parameters/prm_support.h"

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <utility>
#include <vector>

#include "common/input_error.h"
#include "common/number_text.h"

namespace trackbed::cases {

void declare_vector(dealii::ParameterHandler& prm, const std::string& name, const std::string& def,
                    const std::string& doc) {
  prm.declare_entry(name, def, dealii::Patterns::List(dealii::Patterns::Double(), 3, 3), doc);
}

dem::Vec3 vector_of(const dealii::ParameterHandler& prm, const std::string& name) {
  const auto v =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(name)));
  return dem::Vec3(v[0], v[1], v[2]);
}

std::string output_folder_of(const dealii::ParameterHandler& prm, const ParameterSource& in) {
  const std::string folder = prm.get("folder");
  if (folder.empty()) throw InputError(in.path + ": output/folder is empty; valid: a folder name");
  return folder;
}

std::string name_of(const dealii::ParameterHandler& prm, const std::string& where) {
  const std::string name = prm.get("name");
  const bool valid =
      !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
      });
  if (!valid)
    throw InputError(where + "name = '" + excerpt(name) +
                     "': valid: 1 to 64 letters, digits, '_', '-' or '.' (names head CSV "
                     "columns and summary keys)");
  return name;
}

InputError value_error(const std::string& path, const std::exception& e) {
  return InputError(path + ": " + one_line(e) +
                    "; valid: a number of normal size (about 1e-300 to 1e300), an integer "
                    "within range");
}

std::array<double, 6> six_of(const dealii::ParameterHandler& prm, const std::string& name) {
  const auto v =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(name)));
  return {{v[0], v[1], v[2], v[3], v[4], v[5]}};
}

void declare_material_values(dealii::ParameterHandler& prm, const dem::Material& d,
                             const std::string& role) {
  using dealii::Patterns::Double;
  prm.declare_entry("density", number_text(d.density), Double(1e-9),
                    "kg/m^3" + (role.empty() ? std::string() : " (" + role + ")"));
  prm.declare_entry("normal stiffness", number_text(d.normal_stiffness), Double(1e-9, 1e15),
                    "Entity normal stiffness, N/m (pairs combine in series unless a contact "
                    "pair gives its own value)");
  prm.declare_entry("shear stiffness", number_text(d.shear_stiffness), Double(0, 1e15),
                    "Entity shear stiffness, N/m");
  prm.declare_entry("friction", number_text(d.friction), Double(0, 100),
                    "Coulomb friction coefficient");
  prm.declare_entry("rolling friction", number_text(d.rolling_friction), Double(0, 100),
                    "Rolling resistance coefficient mu_r (0: none)");
  prm.declare_entry("normal damping ratio", number_text(d.normal_damping_ratio), Double(0, 1),
                    "Normal dashpot, fraction of critical");
  prm.declare_entry("shear damping ratio", number_text(d.shear_damping_ratio), Double(0, 1),
                    "Shear dashpot, fraction of critical");
  prm.declare_entry("normal damping rate", number_text(d.normal_damping_rate), Double(0, 1e9),
                    "Normal dashpot as gamma_n in 1/s: F = gamma_n m_eff v_n (LAMMPS style)");
  prm.declare_entry("local damping", number_text(d.local_damping), Double(0, 0.999),
                    "Local damping coefficient alpha");
}

void read_material_values(const dealii::ParameterHandler& prm, dem::Material& m) {
  m.density = prm.get_double("density");
  m.normal_stiffness = prm.get_double("normal stiffness");
  m.shear_stiffness = prm.get_double("shear stiffness");
  m.friction = prm.get_double("friction");
  m.rolling_friction = prm.get_double("rolling friction");
  m.normal_damping_ratio = prm.get_double("normal damping ratio");
  m.shear_damping_ratio = prm.get_double("shear damping ratio");
  m.normal_damping_rate = prm.get_double("normal damping rate");
  m.local_damping = prm.get_double("local damping");
}

namespace {

std::string trim(std::string t) {
  t.erase(0, t.find_first_not_of(" \t\r"));
  t.erase(t.find_last_not_of(" \t\r") + 1);
  return t;
}

// `word` at the start of `line` followed by a blank or the end, in lower or upper case.
bool starts_with_keyword(const std::string& line, const std::string& word, std::string& rest) {
  std::string upper = word;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const std::string& w : {word, upper})
    if (line.compare(0, w.size(), w) == 0 && (line.size() == w.size() || line[w.size()] == ' ')) {
      rest = trim(line.substr(w.size()));
      return true;
    }
  return false;
}

// The folder of a file, absolute and normalised: where the relative names it gives resolve.
std::string folder_of_file(const std::string& path) {
  return std::filesystem::absolute(path).parent_path().lexically_normal().string();
}

// Follows the subsection nesting of parameter-file text, one line at a time, as deal.II reads it
// (tabs and runs of blanks as one blank, '#' starts a comment, keywords in lower or upper case).
class SectionScanner {
 public:
  // For a 'set' line: true, with `key` the full name ("subsection/.../name") and `value` the
  // trimmed text after '='. 'subsection' and 'end' lines change the nesting; others are ignored.
  bool scan(const std::string& line, std::string& key, std::string& value);

 private:
  std::vector<std::string> path_;
};

bool SectionScanner::scan(const std::string& raw, std::string& key, std::string& value) {
  std::string line;
  for (char c : raw.substr(0, raw.find('#'))) {
    if (c == '\t' || c == '\r') c = ' ';
    if (c == ' ' && !line.empty() && line.back() == ' ') continue;
    line += c;
  }
  line = trim(line);
  std::string rest;
  if (starts_with_keyword(line, "subsection", rest)) {
    path_.push_back(rest);
  } else if (starts_with_keyword(line, "end", rest) && rest.empty()) {
    if (!path_.empty()) path_.pop_back();
  } else if (starts_with_keyword(line, "set", rest)) {
    const std::size_t eq = rest.find('=');
    key.clear();
    for (const auto& p : path_) key += p + "/";
    key += trim(rest.substr(0, eq));
    value = eq == std::string::npos ? "" : trim(rest.substr(eq + 1));
    return true;
  }
  return false;
}

}  // namespace

std::string fingerprint(const dealii::ParameterHandler& prm) {
  std::ostringstream printed;
  prm.print_parameters(printed, dealii::ParameterHandler::ShortPRM);
  std::istringstream in(printed.str());
  SectionScanner sections;
  std::string line, key, value, out;
  static const char* const kIgnored[] = {"simulation/threads", "build/threads", "output/folder",
                                         "output/progress interval", "output/checkpoint interval"};
  while (std::getline(in, line))
    if (sections.scan(line, key, value) &&
        std::find(std::begin(kIgnored), std::end(kIgnored), key) == std::end(kIgnored))
      out += key + " = " + value + "\n";
  return out;
}

std::string one_line(const std::exception& e) {
  std::string text;
  if (const auto* d = dynamic_cast<const dealii::ExceptionBase*>(&e)) {
    std::ostringstream s;
    d->print_info(s);
    text = s.str();
  } else {
    text = e.what();
  }
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == ' ' && (out.empty() || out.back() == ' ')) continue;
    out += c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  // deal.II quotes the values it refuses: a long one is shortened.
  std::istringstream words(out);
  std::string shortened, word;
  while (words >> word) shortened += (shortened.empty() ? "" : " ") + excerpt(word);
  return shortened;
}

namespace {

// A parameter file with its 'include FILE' lines replaced by the files' contents, recursively;
// each included name is relative to the folder of the file that names it. `origin` gives the
// file and line of every line of `text`, for error messages; `set_in` the folder of the file
// whose 'set' line gave each parameter its value.
struct ExpandedFile {
  std::string text;
  std::vector<std::pair<std::string, int>> origin;
  std::map<std::string, std::string> set_in;
  SectionScanner sections;
  bool continued = false;  // the previous line ended with '\': this one is part of its value
};

// Throws InputError at `where` unless `path` is a regular file of a parameter file's size: a
// folder, a FIFO or a device (/dev/zero) would be read forever or as nothing.
void require_parameter_text(const std::string& path, const std::string& where) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(where + ": not a regular file; valid: a .prm text file");
  constexpr std::uintmax_t kMaxBytes = 16u << 20;
  if (fs::file_size(path, ec) > kMaxBytes)
    throw InputError(where + ": larger than 16 MB; valid: a .prm text file");
}

void expand(const std::string& path, ExpandedFile& out, int depth) {
  namespace fs = std::filesystem;
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot be read; valid: a readable .prm file");
  const std::string folder = folder_of_file(path);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t");
    const std::string word = first == std::string::npos ? "" : line.substr(first, 8);
    if (word == "include " || word == "INCLUDE ") {
      const std::string rest = line.substr(first + 8);
      const std::string name = trim(rest.substr(0, rest.find('#')));
      const fs::path target =
          fs::path(name).is_absolute() ? fs::path(name) : fs::path(path).parent_path() / name;
      const std::string where = path + ":" + std::to_string(number) + ": include " + name;
      if (depth >= 16) throw InputError(where + ": includes nested more than 16 deep (a cycle?)");
      if (!fs::exists(target))
        throw InputError(where +
                         ": file not found; valid: a path relative to the folder "
                         "of the including file");
      require_parameter_text(target.string(), where);
      expand(target.lexically_normal().string(), out, depth + 1);
      continue;
    }
    out.text += line + "\n";
    out.origin.emplace_back(path, number);
    std::string key, value;
    if (!out.continued && out.sections.scan(line, key, value)) out.set_in[key] = folder;
    const std::string code = line.substr(0, line.find_last_not_of(" \t\r") + 1);
    out.continued = !code.empty() && code.back() == '\\';
  }
}

}  // namespace

std::string ValueFolders::folder_of(const std::string& key) const {
  const auto it = set_in_.find(key);
  return it == set_in_.end() ? top_ : it->second;
}

std::string ValueFolders::resolve(const std::string& key, const std::string& value) const {
  namespace fs = std::filesystem;
  if (value.empty() || fs::path(value).is_absolute()) return value;
  return (fs::path(folder_of(key)) / value).lexically_normal().string();
}

ValueFolders parse_parameter_file(dealii::ParameterHandler& prm, const std::string& path,
                                  const std::string& print_command) {
  if (!std::filesystem::exists(path))
    throw InputError(path + ": file not found; valid: a .prm file (see '" + print_command + "')");
  require_parameter_text(path, path);
  ExpandedFile file;
  expand(path, file, 0);
  try {
    prm.parse_input_from_string(file.text);
  } catch (const std::exception& e) {
    // deal.II names the line of the expanded text: name the file and line it came from.
    std::string message = one_line(e);
    const std::regex where("Line <([0-9]+)> of file <[^>]*>");
    std::smatch m;
    if (std::regex_search(message, m, where)) {
      const std::size_t k = std::stoul(m[1].str()) - 1;
      if (k < file.origin.size())
        message = m.prefix().str() + "Line <" + std::to_string(file.origin[k].second) +
                  "> of file <" + file.origin[k].first + ">" + m.suffix().str();
    }
    throw InputError(path + ": " + message + "; valid names and ranges: " + print_command);
  }
  ValueFolders folders;
  folders.top_ = folder_of_file(path);
  folders.set_in_ = std::move(file.set_in);
  return folders;
}

}  // namespace trackbed::cases
