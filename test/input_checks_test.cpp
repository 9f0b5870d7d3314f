// SPDX-License-Identifier: BSD-3-Clause
// The core's entry points refuse bad input up front, class by class, with messages naming the file or field
// and the allowed range: image sizes, image files (truncated, corrupt, not images), calibration YAML (shape
// and plausibility), YAML that is not what it should be.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>

#include <jpeglib.h>

#include "underwater_stereo/common/calibration_yaml.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/detection/image_file.h"

using namespace underwater_stereo;

namespace {

std::string tempFile(const std::string& name, const std::string& bytes) {
  const std::string path = testing::TempDir() + "uws_checks_" + std::to_string(::getpid()) + "_" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

template <typename F>
std::string messageOf(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

/// `image` encoded as `ext` (any depth the format takes).
std::string encodedImage(const std::string& ext, const cv::Mat& image) {
  std::vector<uchar> bytes;
  cv::imencode(ext, image, bytes);
  return std::string(bytes.begin(), bytes.end());
}

std::string encoded(const std::string& ext, cv::Size size = cv::Size(64, 48)) {
  cv::Mat image(size, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
  return encodedImage(ext, image);
}

const char* kGoodCalibration = R"(image_width: 640
image_height: 400
camera_name: left
camera_matrix: {rows: 3, cols: 3, data: [500, 0, 320, 0, 500, 200, 0, 0, 1]}
distortion_model: plumb_bob
distortion_coefficients: {rows: 1, cols: 5, data: [0.01, -0.02, 0, 0, 0]}
rectification_matrix: {rows: 3, cols: 3, data: [1, 0, 0, 0, 1, 0, 0, 0, 1]}
projection_matrix: {rows: 3, cols: 4, data: [500, 0, 320, 0, 0, 500, 200, 0, 0, 0, 1, 0]}
)";

/// The good calibration with `from` replaced by `to`.
std::string calibrationWith(const std::string& from, const std::string& to) {
  std::string s = kGoodCalibration;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

}  // namespace

TEST(ImageSize, TheRangeDependsOnTheSearchScale) {
  EXPECT_EQ(imageSizeProblem(32, 32), "");
  EXPECT_EQ(imageSizeProblem(16384, 2025), "");  // 8K UHD's pixels
  EXPECT_EQ(imageSizeProblem(16384, 16384), "image size 16384x16384 has 268435456 pixels, more than 33177600 (8K UHD)");
  EXPECT_EQ(imageSizeProblem(1, 1), "image size 1x1 is outside 32..16384 px per side");
  EXPECT_NE(imageSizeProblem(16385, 100).find("outside"), std::string::npos);
  EXPECT_NE(imageSizeProblem(4294967296LL, 100).find("4294967296x100"), std::string::npos);
  EXPECT_EQ(minImageSidePx(0.5), 32);
  EXPECT_EQ(minImageSidePx(0.1), 160);
  EXPECT_NE(imageSizeProblem(2000, 2, 0.1).find("(search_scale 0.1 needs >= 160)"), std::string::npos);
}

TEST(ImageSize, TheDetectorRefusesFramesTooSmallOrThinForItsStages) {
  DetectorConfig config = loadDetectorConfigFile(std::string(UWS_SOURCE_DIR) + "/config/detector.yaml");
  const Detector flat(config);
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(1, 1200), cv::Size(1920, 1), cv::Size(2000, 1), cv::Size(31, 400)}) {
    const std::string m = messageOf([&] { flat.detect2d(cv::Mat(size, CV_8UC3, cv::Scalar(100, 90, 40))); });
    EXPECT_NE(m.find("Detector::detect2d: image size"), std::string::npos) << m;
  }
  config.search_scale = 0.1;
  const std::string m = messageOf([&] { Detector(config).detect2d(cv::Mat(2000, 2, CV_8UC3, cv::Scalar(1, 2, 3))); });
  EXPECT_NE(m.find("search_scale 0.1 needs >= 160"), std::string::npos) << m;
  // The smallest accepted frame runs through every 2D stage.
  EXPECT_NO_THROW(Detector(config).detect2d(cv::Mat(160, 160, CV_8UC3, cv::Scalar(30, 30, 200))));
  EXPECT_NO_THROW(flat.detect2d(cv::Mat(32, 32, CV_8UC3, cv::Scalar(30, 30, 200))));
}

TEST(ImageFile, IntactFilesAreReadAsImreadReadsThem) {
  for (const std::string ext : {".png", ".jpg", ".bmp"}) {
    const std::string path = tempFile("good" + ext, encoded(ext));
    const cv::Mat read = readImageFile(path);
    EXPECT_EQ(cv::norm(read, cv::imread(path, cv::IMREAD_COLOR), cv::NORM_INF), 0.0) << ext;
  }
}

TEST(ImageFile, AnExifOrientationIsIgnoredThePixelsStayAsTheSensorWroteThem) {
  // A JPEG whose EXIF says "rotate 90 degrees clockwise to view" (orientation 6): a camera's calibration and a
  // VOC tool's boxes are in the stored pixel layout, so the image is read as stored, not turned.
  cv::Mat image(48, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  image(cv::Rect(0, 0, 16, 12)).setTo(cv::Scalar(255, 255, 255));
  std::string jpeg = encodedImage(".jpg", image);
  const std::string tiff("MM\0*\0\0\0\x08\0\x01\x01\x12\0\x03\0\0\0\x01\0\x06\0\0\0\0\0\0", 26);
  const std::string exif = std::string("Exif\0\0", 6) + tiff;
  const std::string app1 = std::string("\xff\xe1", 2) + char((exif.size() + 2) >> 8) + char((exif.size() + 2) & 0xff) + exif;
  jpeg.insert(2, app1);
  const std::string path = tempFile("exif6.jpg", jpeg);
  ASSERT_EQ(cv::imread(path, cv::IMREAD_COLOR).size(), cv::Size(48, 64)) << "the EXIF tag is not the one OpenCV reads";
  const cv::Mat read = readImageFile(path);
  ASSERT_EQ(read.size(), image.size());
  EXPECT_GT(cv::mean(read(cv::Rect(0, 0, 16, 12)))[0], 200.0);
}

TEST(ImageFile, SixteenBitAndFloatingPointImagesAreReadAsTheirBrightness) {
  cv::Mat eight(48, 64, CV_8UC3);
  cv::randu(eight, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::Mat sixteen, floating;
  eight.convertTo(sixteen, CV_16U, 257.0);
  eight.convertTo(floating, CV_32F, 1.0 / 255.0);
  EXPECT_EQ(cv::norm(readImageFile(tempFile("sixteen.png", encodedImage(".png", sixteen))), eight, cv::NORM_INF), 0.0);
  // OpenCV's own IMREAD_COLOR of a 0..1 float TIFF is not linear (a mid grey comes out far brighter); its TIFF
  // writer stores three float channels as LogLuv, within about 1 %.
  EXPECT_LE(cv::norm(readImageFile(tempFile("float.tiff", encodedImage(".tiff", floating))), eight, cv::NORM_INF), 5.0);
  const cv::Mat over = readImageFile(tempFile("over.tiff", encodedImage(".tiff", floating * 1.5)));
  // Over 1 (eight >= 170, with the LogLuv margin: 176) is white; under it (<= 165) is not.
  EXPECT_EQ(cv::countNonZero((eight.reshape(1) >= 176) & (over.reshape(1) != 255)), 0);
  EXPECT_EQ(cv::countNonZero((eight.reshape(1) <= 165) & (over.reshape(1) == 255)), 0);
  // An image scaled 0..255 (its median pixel far over 1) would read nearly all white: refused, saying why.
  const std::string scaled = tempFile("scaled.tiff", encodedImage(".tiff", floating * 255.0));
  EXPECT_NE(messageOf([&] { readImageFile(scaled); }).find(scaled + ": a floating-point image whose median pixel is"),
            std::string::npos);
  // Signed integers are refused by the reader, naming the file (OpenCV writes no three-channel ones to try).
  const cv::Mat signed_ints(48, 64, CV_32SC1, cv::Scalar(7));
  const std::string ints = tempFile("int32.tiff", encodedImage(".tiff", signed_ints));
  EXPECT_NE(messageOf([&] { readImageFile(ints); }).find(ints + ": pixels of 32-bit signed integers"),
            std::string::npos);
  // 64-bit floating-point grey (cvtColor takes no 64-bit pixels; OpenCV writes no 64-bit colour TIFF to try).
  const cv::Mat doubles(48, 64, CV_64FC1, cv::Scalar(0.5));
  const cv::Mat read_doubles = readImageFile(tempFile("doubles.tiff", encodedImage(".tiff", doubles)));
  EXPECT_EQ(read_doubles.type(), CV_8UC3);
  EXPECT_NEAR(cv::mean(read_doubles)[0], 127.5, 1.0);
  const std::string huge_doubles = tempFile("huge_doubles.tiff", encodedImage(".tiff", cv::Mat(48, 64, CV_64FC1, cv::Scalar(1e40))));
  EXPECT_NE(messageOf([&] { readImageFile(huge_doubles); }).find(huge_doubles + ": a floating-point image whose median pixel is"),
            std::string::npos)
      << messageOf([&] { readImageFile(huge_doubles); });  // beyond 32-bit floats: too bright, not "infinite"
  cv::Mat with_nan(48, 64, CV_32F, cv::Scalar(0.5));  // one channel: stored as plain floats, NaN kept
  with_nan.at<float>(3, 4) = std::numeric_limits<float>::quiet_NaN();
  const std::string nan = tempFile("nan.tiff", encodedImage(".tiff", with_nan));
  EXPECT_NE(messageOf([&] { readImageFile(nan); }).find(nan + ": a floating-point image with NaN or infinite pixels"),
            std::string::npos);
  cv::Mat grey(48, 64, CV_8UC1);
  cv::randu(grey, 0, 256);
  const cv::Mat read_grey = readImageFile(tempFile("grey.png", encodedImage(".png", grey)));
  EXPECT_EQ(read_grey.type(), CV_8UC3);
  EXPECT_TRUE(isGreyImage(read_grey));
  EXPECT_FALSE(isGreyImage(eight));
}

TEST(ImageFile, ACmykJpegIsReadAsOpenCvReadsIt) {
  // Written by libjpeg itself (OpenCV writes no CMYK): every pixel C 0, M 128, Y 255, K 0 as libjpeg stores CMYK.
  constexpr int kWidth = 48, kHeight = 40;
  std::vector<unsigned char> row(4 * kWidth);
  for (int x = 0; x < kWidth; ++x) {
    row[4 * x] = 255, row[4 * x + 1] = 128, row[4 * x + 2] = 0, row[4 * x + 3] = 255;
  }
  jpeg_compress_struct cinfo;
  jpeg_error_mgr errors;
  cinfo.err = jpeg_std_error(&errors);
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = kWidth;
  cinfo.image_height = kHeight;
  cinfo.input_components = 4;
  cinfo.in_color_space = JCS_CMYK;
  jpeg_set_defaults(&cinfo);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW r = row.data();
    jpeg_write_scanlines(&cinfo, &r, 1);
  }
  jpeg_finish_compress(&cinfo);
  const std::string bytes(reinterpret_cast<const char*>(buffer), size);
  jpeg_destroy_compress(&cinfo);
  std::free(buffer);
  const std::string path = tempFile("cmyk.jpg", bytes);
  const cv::Mat opencv = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_EQ(opencv.size(), cv::Size(kWidth, kHeight));
  const cv::Mat read = readImageFile(path);
  EXPECT_EQ(cv::norm(read, opencv, cv::NORM_INF), 0.0);
}

TEST(ImageFile, TruncatedCorruptEmptyAndNonImageFilesAreRefusedNamingTheFile) {
  const std::string jpeg = encoded(".jpg", cv::Size(320, 240)), png = encoded(".png");
  std::string corrupt = jpeg;
  for (std::size_t i = jpeg.size() / 2; i < jpeg.size() / 2 + 40; ++i) corrupt[i] = static_cast<char>(0xff);
  const std::vector<std::tuple<std::string, std::string, std::string>> cases{
      {"cut.jpg", jpeg.substr(0, jpeg.size() / 2), "corrupt or truncated JPEG (Premature end of JPEG file)"},
      {"cut_end.jpg", jpeg.substr(0, jpeg.size() - 2), "Premature end of JPEG file"},
      {"header_only.jpg", jpeg.substr(0, 300), "corrupt or truncated JPEG"},
      {"corrupt.jpg", corrupt, "corrupt or truncated JPEG"},
      {"cut.png", png.substr(0, png.size() / 2), "truncated PNG (the file does not end with its IEND chunk)"},
      {"stub.png", png.substr(0, 20), "truncated PNG (20 bytes)"},
      {"empty.png", "", "empty file"},
      {"text.jpg", "this is not an image\n", "not an image OpenCV can read"},
      {"tiny.png", encoded(".png", cv::Size(1, 1)), "image size 1x1 is outside 32..16384"},
      {"thin.jpg", encoded(".jpg", cv::Size(2000, 1)), "image size 2000x1 is outside"},
  };
  for (const auto& [name, bytes, expected] : cases) {
    const std::string path = tempFile(name, bytes);
    const std::string m = messageOf([&] { readImageFile(path); });
    EXPECT_NE(m.find(path + ": "), std::string::npos) << name << ": " << m;
    EXPECT_NE(m.find(expected), std::string::npos) << name << ": " << m;
  }
  EXPECT_NE(messageOf([] { readImageFile("/nonexistent/x.png"); }).find("/nonexistent/x.png: No such file or directory"), std::string::npos);
  EXPECT_NE(messageOf([] { readImageFile(testing::TempDir()); }).find(": a folder, not a file"), std::string::npos);
  // A device that never ends, and a pipe with no writer (fopen would wait for one for ever): refused before reading.
  EXPECT_NE(messageOf([] { readImageFile("/dev/zero"); }).find("/dev/zero: not a regular file"), std::string::npos);
  const std::string fifo = testing::TempDir() + "/uws_no_writer.fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(messageOf([&] { readImageFile(fifo); }).find(fifo + ": not a regular file"), std::string::npos);
  std::remove(fifo.c_str());
  // A read that fails part way (reading /proc/self/mem from address 0 fails with EIO): the system's reason.
  EXPECT_NE(messageOf([] { readImageFile("/proc/self/mem"); }).find("/proc/self/mem: Input/output error"), std::string::npos)
      << messageOf([] { readImageFile("/proc/self/mem"); });
  // A PNG header declaring a huge image is refused before anything is decoded.
  std::string huge = png;
  huge[16] = 0x00, huge[17] = 0x01, huge[18] = 0x00, huge[19] = 0x00;  // width 65536
  EXPECT_NE(messageOf([&] { readImageFile(tempFile("huge.png", huge)); }).find("image size 65536x48"), std::string::npos);
}

TEST(CalibrationYaml, TheGoodFileIsReadWithEveryField) {
  const CameraCalibration c = loadCameraCalibrationFile(tempFile("good.yaml", kGoodCalibration));
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.K(1, 2), 200);
  EXPECT_EQ(c.D.size(), 5U);
  EXPECT_EQ(c.P(1, 1), 500);
  EXPECT_EQ(c.distortion_model, DistortionModel::kPlumbBob);
}

TEST(CalibrationYaml, EveryShapeAndValueProblemIsListedNamingTheFileAndField) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {calibrationWith("camera_matrix: {rows: 3", "camera_matrix: {rows: 2"), "camera_matrix.rows: must be 3, is 2"},
      {calibrationWith("cols: 4, data: [500, 0, 320, 0, 0, 500, 200, 0, 0, 0, 1, 0]", "cols: 4, data: [500, 0]"),
       "projection_matrix.data: has 2 numbers, rows x cols = 3x4 needs 12"},
      {calibrationWith("rows: 1, cols: 5, data: [0.01, -0.02, 0, 0, 0]", "rows: 1, cols: 3, data: [0.01, -0.02, 0]"),
       "D has 3 coefficients"},
      {calibrationWith("plumb_bob", "equidistant"), "distortion_model: 'equidistant' is not supported"},
      {calibrationWith("image_width: 640", "image_width: wide"), "image_width: expected an integer, got 'wide'"},
      {calibrationWith("image_width: 640\n", ""), "image_width: missing"},
      {calibrationWith("projection_matrix:", "projection_matrx:"), "projection_matrx: unknown key"},
      {calibrationWith("data: [500, 0, 320, 0, 500, 200, 0, 0, 1]", "data: [1e-6, 0, 320, 0, 1e-6, 200, 0, 0, 1]"),
       "K[0] (fx) = 1e-06 px is outside 50..20000"},
      {calibrationWith("data: [500, 0, 320, 0, 500, 200, 0, 0, 1]", "data: [500, 0, 1e9, 0, 500, 200, 0, 0, 1]"),
       "principal point cx = 1e+09 is outside the image (0..640)"},
      {calibrationWith("[0.01, -0.02, 0, 0, 0]", "[500, -500, 0, 0, 0]"), "distortion coefficient 500 is outside -10..10"},
      {calibrationWith("data: [500, 0, 320, 0, 500, 200, 0, 0, 1]", "data: [500, 0, .nan, 0, 500, 200, 0, 0, 1]"),
       "NaN"},
      {calibrationWith("camera_matrix: {rows: 3, cols: 3, data: [500, 0, 320, 0, 500, 200, 0, 0, 1]}", "camera_matrix: 7"),
       "camera_matrix: expected a map"},
      {"[1, 2, 3]", "document: expected a map"},
      {"", "document: expected a map"},
      {"image_width: [unclosed", "cannot read camera calibration"},
      {"{[a]: 1}", "unknown key"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string path = tempFile("bad.yaml", yaml);
    const std::string m = messageOf([&] { loadCameraCalibrationFile(path); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(expected), std::string::npos) << "expected '" << expected << "' in: " << m;
  }
  EXPECT_NE(messageOf([] { loadCameraCalibrationFile("/nonexistent.yaml"); }).find("cannot read camera calibration '/nonexistent.yaml'"),
            std::string::npos);
  EXPECT_NE(messageOf([] { loadCameraCalibrationFile(testing::TempDir()); }).find("': a folder, not a file"),
            std::string::npos) << "yaml-cpp alone says only 'basic_filebuf::underflow error'";
}

TEST(CalibrationYaml, ANanFocalLengthIsNamedOnceNotAlsoAsSkew) {
  CameraCalibration c = parseCameraCalibration(YAML::Load(kGoodCalibration));
  c.K(0, 0) = std::numeric_limits<double>::quiet_NaN();
  std::string all;
  for (const std::string& p : c.validate("left")) all += p + "\n";
  EXPECT_NE(all.find("K[0] (fx) = nan px is outside"), std::string::npos) << all;
  EXPECT_EQ(all.find("skew"), std::string::npos) << all;
  c = parseCameraCalibration(YAML::Load(kGoodCalibration));
  c.K(0, 1) = 80;  // more than 0.1 fx: still named
  all.clear();
  for (const std::string& p : c.validate("left")) all += p + "\n";
  EXPECT_NE(all.find("K skew 80 exceeds 0.1 * fx"), std::string::npos) << all;
}

TEST(CalibrationYaml, APairWithAnImplausibleBaselineIsRefused) {
  StereoCalibration pair{parseCameraCalibration(YAML::Load(kGoodCalibration)),
                         parseCameraCalibration(YAML::Load(kGoodCalibration))};
  pair.right.P(0, 3) = -500 * 1e12;
  std::vector<std::string> problems = pair.validate();
  ASSERT_EQ(problems.size(), 1U);
  EXPECT_EQ(problems[0], "baseline -P_right[3] / P_right[0] = 1e+12 m is outside 0.01..2 m");
  pair.right.P(0, 3) = -500 * 0.12;
  EXPECT_TRUE(pair.validate().empty());
}

TEST(DetectorConfigYaml, YamlOfTheWrongShapeIsRefusedNotThrownThrough) {
  for (const std::string yaml : {"{[a]: 1}", "quality: 5", "colours: {a: 1}", "colours: [1, 2]", "search_scale: [1]",
                                 "stereo: {block_size: .nan}", "- 1", "quality: {too_dark_below: {x: 1}}"}) {
    const std::string path = tempFile("config.yaml", yaml);
    const std::string m = messageOf([&] { loadDetectorConfigFile(path); });
    EXPECT_NE(m.find(path), std::string::npos) << yaml << ": " << m;
  }
}
