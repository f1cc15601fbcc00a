#pragma once
// Internal to libism/io: the pieces the mesh readers share. Every reader works
// on the whole file in memory and only moves forward through it, so each loop
// either consumes input or ends; every count a file declares is checked
// against the bytes left before anything is reserved for it (an element takes
// at least one byte, a text number at least two with its separator).
#include "io/io.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace ism::io::detail {

/// A reader's error: FileError with the file's name (and line, when known).
[[noreturn]] void fail(const std::string& name, const std::string& why);
[[noreturn]] void fail_at(const std::string& name, std::size_t line, const std::string& why);

/// Throws when `count` items of at least `min_bytes` each cannot fit in
/// `bytes_left` bytes: a header that claims more than the file holds.
void check_count(const std::string& name, const char* what, std::uint64_t count,
                 std::size_t min_bytes, std::size_t bytes_left);

/// Up to 40 characters of file content for a message, quoted, with bytes
/// that are not printable ASCII shown as '?': a message stays one line.
std::string quoted(std::string_view content);

/// A number for a message: integral values without decimals.
std::string number_text(double value);

/// Text without a UTF-8 byte-order mark; throws for UTF-16/UTF-32 text,
/// which no mesh reader understands.
std::string_view strip_byte_order_mark(std::string_view text, const std::string& name);

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Cursor over one line (or any span) of text: whitespace-separated words
/// and numbers. Never reads outside its span.
class Words {
 public:
  explicit Words(std::string_view text) : text_(text) {}
  bool done() {
    skip();
    return at_ == text_.size();
  }
  std::string_view next() {
    skip();
    const std::size_t start = at_;
    while (at_ < text_.size() && !is_space(text_[at_]) && text_[at_] != '\n') ++at_;
    return text_.substr(start, at_ - start);
  }
  std::string_view rest() {
    skip();
    return text_.substr(at_);
  }

 private:
  void skip() {
    while (at_ < text_.size() && (is_space(text_[at_]) || text_[at_] == '\n')) ++at_;
  }
  std::string_view text_;
  std::size_t at_ = 0;
};

/// The whole word as a double (a leading '+' allowed, "nan"/"inf" accepted
/// and left to the mesh checks); false when it is not a number.
inline bool parse_double(std::string_view word, double& value) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  if (word.empty()) return false;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec == std::errc::result_out_of_range) {
    // Overflow or underflow of a well-formed number: keep it as inf or 0.
    value = std::strtod(std::string(word).c_str(), nullptr);
    return true;
  }
  return ec == std::errc() && end == word.data() + word.size();
}

/// The whole word as a 64-bit integer; false when it is not one (or overflows).
inline bool parse_integer(std::string_view word, std::int64_t& value) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  if (word.empty()) return false;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc() && end == word.data() + word.size();
}

/// Lines of a text, numbered from 1, '\n' or "\r\n" endings, the last line
/// possibly without one.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (at_ >= text_.size()) return false;
    const void* nl = std::memchr(text_.data() + at_, '\n', text_.size() - at_);
    const std::size_t end =
        nl ? std::size_t(static_cast<const char*>(nl) - text_.data()) : text_.size();
    line = text_.substr(at_, end - at_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    at_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }
  std::size_t bytes_left() const { return at_ >= text_.size() ? 0 : text_.size() - at_; }
  /// The text from the current position on.
  std::string_view rest() const {
    return at_ >= text_.size() ? std::string_view() : text_.substr(at_);
  }

 private:
  std::string_view text_;
  std::size_t at_ = 0;
  std::size_t number_ = 0;
};

/// The formats' readers: positions and faces as the file has them (indices
/// 0-based but not yet checked against the vertex count).
PolygonSoup parse_obj(std::string_view bytes, const std::string& name);
PolygonSoup parse_off(std::string_view bytes, const std::string& name);
PolygonSoup parse_ply(std::string_view bytes, const std::string& name);
PolygonSoup parse_stl(std::string_view bytes, const std::string& name);

/// Declared sizes from the first bytes of a file (`head`, its first
/// kPeekBytes or all of it) and its size, capped by what the size can hold
/// (see peek_mesh_size).
constexpr std::size_t kPeekBytes = 1 << 16;
MeshFileSize peek_off(std::string_view head, std::uint64_t file_bytes, const std::string& name);
MeshFileSize peek_ply(std::string_view head, std::uint64_t file_bytes, const std::string& name);
MeshFileSize peek_stl(std::string_view head, std::uint64_t file_bytes);

/// Counts an OBJ's v and f lines from successive chunks of the file.
class ObjLineCounter {
 public:
  void feed(std::string_view chunk);
  MeshFileSize size(std::uint64_t file_bytes) const { return {file_bytes, vertices_, faces_}; }

 private:
  std::uint64_t vertices_ = 0, faces_ = 0;
  int state_ = 0;  // position in the current line: 0 start, 1 after 'v', 2 after 'f', 3 other
};

}  // namespace ism::io::detail
