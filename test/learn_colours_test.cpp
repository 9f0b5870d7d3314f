// SPDX-License-Identifier: BSD-3-Clause
// learn_colours end to end: frames and VOC labels that render_scene wrote, learnt over the default configuration,
// give a configuration that loads wherever it was written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "underwater_stereo/detection/detector_config.h"

namespace fs = std::filesystem;
using namespace underwater_stereo;

namespace {

int run(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " >" + log.string() + " 2>&1").c_str());
  return WEXITSTATUS(status);
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(LearnColours, AConfigLearntOverTheDefaultLoadsFromAnotherFolder) {
  const fs::path dir = fs::temp_directory_path() / ("learn_colours_test_" + std::to_string(::getpid()));
  fs::create_directories(dir / "pool");
  ASSERT_EQ(run(std::string(UWS_RENDER_SCENE) + " --random 10 --seed 50000 --size 640x400 --out " + (dir / "sim").string(),
                dir / "render.log"),
            0)
      << read(dir / "render.log");
  // Orange and yellow are taught as background: two colours are enough here, and ten scenes hold both.
  const std::string learn = std::string(UWS_LEARN_COLOURS) + " --images " + (dir / "sim/images").string() +
                            " --annotations " + (dir / "sim/annotations").string() + " --base " UWS_SOURCE_DIR
                            "/config/detector.yaml --colours red,green --background orange,yellow --folds 1 --out " +
                            (dir / "pool/pool.yaml").string();
  ASSERT_EQ(run(learn, dir / "learn.log"), 0) << read(dir / "learn.log");
  // The base's check after stereo read the base's colour model's votes: said, and not written.
  EXPECT_NE(read(dir / "learn.log").find("check_file is neither used nor written"), std::string::npos);
  const std::string written = read(dir / "pool/pool.yaml");
  EXPECT_EQ(written.find("check_file"), std::string::npos) << written;
  // The base's shape model, named relative to the base's folder, is still found from the new one.
  const DetectorConfig c = loadDetectorConfigFile((dir / "pool/pool.yaml").string());
  EXPECT_TRUE(c.shape.model);
  ASSERT_TRUE(c.learned.model);
  EXPECT_EQ(c.learned.model->colours(), (std::vector<std::string>{"red", "green"}));
  EXPECT_FALSE(c.learned.check);
  fs::remove_all(dir);
}
