#include "io/io.hpp"
#include "io/mesh_parse.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ism::io {

VertexField read_vertex_field(const std::filesystem::path& path, std::size_t rows) {
  using detail::Lines;
  using detail::parse_double;
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(name + ": cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string bytes = text.str();
  VertexField field;
  Lines lines(bytes);
  std::string_view line;
  std::size_t read = 0;
  while (lines.next(line)) {
    std::string copy(line);
    for (char& c : copy)
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    std::istringstream words(copy);
    std::string word;
    std::size_t columns = 0;
    bool comment = false;
    while (words >> word) {
      if (columns == 0 && word[0] == '#') {
        comment = true;
        break;
      }
      double value = 0;
      if (!parse_double(word, value) || !std::isfinite(value))
        throw FileError(name + ":" + std::to_string(lines.number()) + ": '" + word +
                        "' is not a finite number");
      field.values.push_back(value);
      ++columns;
    }
    if (comment || columns == 0) continue;
    if (field.columns == 0) field.columns = columns;
    if (columns != field.columns)
      throw FileError(name + ":" + std::to_string(lines.number()) + ": " + std::to_string(columns) +
                      " values, the first row has " + std::to_string(field.columns));
    if (++read > rows)
      throw FileError(name + ":" + std::to_string(lines.number()) + ": more rows than the " +
                      std::to_string(rows) + " vertices of the mesh");
  }
  if (read != rows)
    throw FileError(name + ": " + std::to_string(read) + " rows, the mesh has " +
                    std::to_string(rows) + " vertices (one row per vertex)");
  return field;
}

void write_vertex_field(const VertexField& field, const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.string().c_str(), "w");
  if (!file) throw FileError(path.string() + ": cannot write the file");
  for (std::size_t r = 0; r < field.rows(); ++r)
    for (std::size_t c = 0; c < field.columns; ++c)
      std::fprintf(file, c + 1 < field.columns ? "%.17g " : "%.17g\n",
                   field.values[r * field.columns + c]);
  const bool ok = !std::ferror(file);
  if (std::fclose(file) != 0 || !ok) throw FileError(path.string() + ": cannot write the file");
}

}  // namespace ism::io
