#include "report/report.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace ism {
namespace {

TEST(Json, ObjectsKeepInsertionOrderAndEscapeStrings) {
  Json j = Json::object();
  j["zeta"] = 1;
  j["alpha"] = "a \"quoted\"\nline";
  j["list"].push_back(true);
  j["list"].push_back(nullptr);
  j["nested"]["x"] = 0.5;
  EXPECT_EQ(j.dump(-1),
            R"({"zeta":1,"alpha":"a \"quoted\"\nline","list":[true,null],"nested":{"x":0.5}})");
  EXPECT_TRUE(j.contains("nested"));
  EXPECT_FALSE(j.contains("missing"));
  EXPECT_EQ(j.size(), 4u);
}

TEST(Json, InvalidUtf8IsReplacedNotThrown) {
  Json j = Json::object();
  j["file"] = std::string("bad\xff.obj");
  EXPECT_EQ(report_text(j), "{\n  \"file\": \"bad\xef\xbf\xbd.obj\"\n}");
}

TEST(Json, NonFiniteNumbersBecomeNull) {
  Json j = Json::array();
  j.push_back(std::numeric_limits<double>::infinity());
  j.push_back(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(j.dump(-1), "[null,null]");
}

TEST(Json, IndentedOutput) {
  Json j = Json::object();
  j["a"] = 1;
  j["b"] = Json::array();
  j["c"]["d"] = 0.25;
  EXPECT_EQ(report_text(j), "{\n  \"a\": 1,\n  \"b\": [],\n  \"c\": {\n    \"d\": 0.25\n  }\n}");
}

TEST(Json, MeshCheckHasTheKeysToolsRelyOn) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const Json j = to_json(prepare_mesh(s).check);
  for (const char* key : {"vertices", "faces", "components", "boundary_loops", "genus", "manifold"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_NE(j.dump(-1).find("\"genus\":0"), std::string::npos);
}

}  // namespace
}  // namespace ism
