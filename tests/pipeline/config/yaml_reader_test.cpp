#include "pipeline/config/yaml_reader.h"

#include <gtest/gtest.h>

#include <string>

#include "common/input_error.h"

namespace agv::pipeline {
namespace {

// The message of the InputError that `read` throws ("" when none).
template <typename Read>
std::string message_of(Read read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A key nobody asked for is refused by finish(), with the file's name and the key's path, also
// inside an item of a list (the unknown-key check must walk into sequences).
TEST(YamlReader, AnUnknownKeyIsNamedEvenInsideAListItem) {
  const std::string text =
      "path:\n"
      "  segments:\n"
      "    - {kind: line, length_m: 1.0}\n"
      "    - {kind: arc, radius_m: 0.5, angle_rad: 1.0, radus_m: 2}\n";
  YamlReader in(parse_yaml(text, "bend.yaml"), "bend.yaml");
  ASSERT_EQ(in.sequence_size("path.segments"), 2u);
  for (int i = 0; i < 2; ++i) {
    const std::string k = "path.segments." + std::to_string(i) + ".";
    in.text(k + "kind", "line");
    in.number(k + "length_m", 1.0, 0.0, 100.0);
    in.number(k + "radius_m", 1.0, 0.0, 100.0);
    in.number(k + "angle_rad", 1.0, -10.0, 10.0);
  }
  const std::string message = message_of([&] { in.finish(); });
  EXPECT_NE(message.find("bend.yaml"), std::string::npos) << message;
  EXPECT_NE(message.find("radus_m"), std::string::npos) << message;
}

// Values are checked by type and range, naming the key; a --set override names the option.
TEST(YamlReader, BadValuesAreNamedByKeyAndOrigin) {
  YamlReader in(parse_yaml("duration_s: -3\nname: [1, 2]\nts: .nan\n", "s.yaml"), "s.yaml");
  std::string message = message_of([&] { in.number("duration_s", 1.0, 0.0, 60.0); });
  EXPECT_NE(message.find("duration_s"), std::string::npos) << message;
  EXPECT_NE(message.find("s.yaml"), std::string::npos) << message;
  message = message_of([&] { in.text("name", ""); });
  EXPECT_NE(message.find("name"), std::string::npos) << message;
  message = message_of([&] { in.number("ts", 0.1, 0.0, 1.0); });
  EXPECT_NE(message.find("ts"), std::string::npos) << message;
  in.set_override("speed_m_s", "abc");
  message = message_of([&] { in.number("speed_m_s", 0.3, 0.0, 2.0); });
  EXPECT_NE(message.find("--set speed_m_s=abc"), std::string::npos) << message;
}

}  // namespace
}  // namespace agv::pipeline
