// The merge of the farm's task records into run.json (pipeline/farm/farm.h mergeStageRecords),
// without Slurm: seconds add up, every task is listed, and the tasks' per-frame seconds join in
// frame order whatever order the tasks come in.
#include "pipeline/farm/farm.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>

namespace kurage::pipeline {
namespace {

using nlohmann::json;

// A task's record as `kurage render --task` writes it: its stage entry with per_frame.
json taskRecord(const std::string& stage, double seconds, const json& frames, const json& frameSeconds) {
  return {{"stages", {{stage, {{"seconds", seconds}, {"per_frame", {{"frame", frames}, {"seconds", frameSeconds}}}}}}}};
}

TEST(FarmMerge, TwoTasksPerFrameSecondsJoinInFrameOrder) {
  // The later chunk first, and within it the frames not in order (as a rerun makes only some).
  const std::vector<std::pair<std::string, json>> records = {
      {"render-3-5.json", taskRecord("render", 2.5, {5, 3, 4}, {0.5, 0.3, 0.4})},
      {"render-0-2.json", taskRecord("render", 1.0, {0, 1, 2}, {0.25, 0.125, 0.5})},
  };
  const json merged = mergeStageRecords("render", records, 6);
  EXPECT_DOUBLE_EQ(merged.at("seconds").get<double>(), 3.5);
  EXPECT_EQ(merged.at("frames"), 6);
  EXPECT_EQ(merged.at("tasks"), json::parse(R"([{"record": "render-3-5.json", "seconds": 2.5},
                                                {"record": "render-0-2.json", "seconds": 1.0}])"));
  EXPECT_EQ(merged.at("per_frame").at("frame"), json({0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(merged.at("per_frame").at("seconds"), json({0.25, 0.125, 0.5, 0.3, 0.4, 0.5}));
}

TEST(FarmMerge, ARecordWithoutTheStageAddsNoFrame) {
  const std::vector<std::pair<std::string, json>> records = {
      {"surface-0-1.json", taskRecord("surface", 2.0, {1, 0}, {0.75, 0.5})},
      {"surface-2-3.json", json{{"stages", {{"render", {{"seconds", 9.0}}}}}}},  // no surface entry
      {"surface-4-5.json", json{{"stages", {{"surface", {{"seconds", 0.5}}}}}}},  // all frames up to date
  };
  const json merged = mergeStageRecords("surface", records, 6);
  EXPECT_DOUBLE_EQ(merged.at("seconds").get<double>(), 2.5);
  EXPECT_EQ(merged.at("tasks").size(), 3u);
  EXPECT_EQ(merged.at("per_frame").at("frame"), json({0, 1}));
  EXPECT_EQ(merged.at("per_frame").at("seconds"), json({0.5, 0.75}));
}

TEST(FarmMerge, PerFrameListsOfDifferentLengthsAreRefusedNamingTheRecord) {
  const std::vector<std::pair<std::string, json>> records = {
      {"render-0-1.json", taskRecord("render", 1.0, {0, 1}, {0.5})}};
  try {
    mergeStageRecords("render", records, 2);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("render-0-1.json: stages.render.per_frame: 2 frames but 1 seconds"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace kurage::pipeline
