#pragma once
// A small JSON value for reports: objects keep their insertion order so that
// reports read in the order the work was done. Non-finite numbers are written
// as null (JSON has no infinity).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace ism {

class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() = default;  // null
  Json(std::nullptr_t) {}
  Json(bool b) : value_(b) {}
  Json(double d) : value_(d) {}
  Json(int i) : value_(std::int64_t(i)) {}
  Json(long i) : value_(std::int64_t(i)) {}
  Json(long long i) : value_(std::int64_t(i)) {}
  Json(unsigned i) : value_(std::int64_t(i)) {}
  Json(unsigned long i) : value_(std::int64_t(i)) {}
  Json(unsigned long long i) : value_(std::int64_t(i)) {}
  Json(const char* s) : value_(std::string(s)) {}
  Json(std::string s) : value_(std::move(s)) {}
  Json(Array a) : value_(std::move(a)) {}

  static Json object() {
    Json j;
    j.value_ = Object{};
    return j;
  }
  static Json array() { return Json(Array{}); }

  /// Object member access; inserts null when absent (turns null into an object).
  Json& operator[](const std::string& key);
  /// Appends to an array (turns null into an array).
  Json& push_back(Json value);

  bool is_null() const { return std::holds_alternative<std::monostate>(value_); }
  bool is_object() const { return std::holds_alternative<Object>(value_); }
  bool is_array() const { return std::holds_alternative<Array>(value_); }
  const Json* find(const std::string& key) const;
  std::size_t size() const;

  /// Serialises with two-space indentation (indent < 0: one line).
  std::string dump(int indent = 2) const;

 private:
  void dump_to(std::string& out, int indent, int depth) const;
  std::variant<std::monostate, bool, std::int64_t, double, std::string, Array, Object> value_;
};

}  // namespace ism
