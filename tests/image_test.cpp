// See image_test.h.
#include "image_test.h"

#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <sstream>

namespace kurage::test {

namespace fs = std::filesystem;

fs::path testOutputFolder(const std::string& name) { return fs::path(KURAGE_BINARY_DIR) / "test_output" / name; }

namespace {

void writeReport(const fs::path& folder, const std::string& name, const std::string& summary, bool haveDiff) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>kurage image test: " << name
       << "</title>\n<style>body{font-family:sans-serif;background:#222;color:#ddd} td{padding:6px;"
          "vertical-align:top;text-align:center} img{image-rendering:pixelated;width:"
          "min(30vw,640px);border:1px solid #555}</style></head>\n<body>\n<h1>"
       << name << "</h1>\n<p>" << summary << "</p>\n<table><tr><th>new</th><th>reference</th><th>difference x10</th></tr>\n"
       << "<tr><td><img src=\"new.png\"></td><td><img src=\"reference.png\"></td><td>"
       << (haveDiff ? "<img src=\"diff.png\">" : "(sizes differ)") << "</td></tr></table>\n"
       << "<p>Accept the new image with <code>KURAGE_UPDATE_REFERENCES=1 ctest -L image</code> after looking at it.</p>\n"
       << "</body></html>\n";
  pipeline::writeTextAtomic(folder / "report.html", html.str());
}

}  // namespace

void expectMatchesReference(const render::Image& actual, const std::string& name, const ImageTolerance& tolerance) {
  const fs::path reference = fs::path(KURAGE_SOURCE_DIR) / "tests/references" / (name + ".png");
  if (const char* update = std::getenv("KURAGE_UPDATE_REFERENCES"); update && std::string(update) != "0") {
    fs::create_directories(reference.parent_path());
    pipeline::writePng(actual, reference);
    std::cout << "updated reference " << reference.string() << "\n";
    return;
  }
  ASSERT_TRUE(fs::exists(reference)) << reference << " is missing; run with KURAGE_UPDATE_REFERENCES=1";
  const render::Image expected = render::readPng(reference);
  // Compare what a PNG holds: the new image quantised to 8 bits as the reference was.
  const fs::path folder = testOutputFolder(name);
  fs::create_directories(folder);
  pipeline::writePng(actual, folder / "new.png");
  const render::Image quantised = render::readPng(folder / "new.png");
  render::CompareOptions options;
  options.pixelThreshold = tolerance.pixelThreshold;
  options.allowedFailingFraction = tolerance.allowedFailingFraction;
  const render::CompareResult result = render::compareImages(quantised, expected, options);
  const bool passed = result.passed && result.meanError <= tolerance.maxMeanError;
  if (passed) {
    std::error_code ignored;
    fs::remove_all(folder, ignored);
    return;
  }
  fs::copy_file(reference, folder / "reference.png", fs::copy_options::overwrite_existing);
  if (result.sizesMatch) pipeline::writePng(render::differenceImage(quantised, expected, 10.0f), folder / "diff.png");
  std::ostringstream summary;
  if (!result.sizesMatch)
    summary << "size " << actual.width() << "x" << actual.height() << ", reference " << expected.width() << "x"
            << expected.height();
  else
    summary << result.failingFraction * 100 << " % of pixels differ by more than " << tolerance.pixelThreshold
            << " (allowed " << tolerance.allowedFailingFraction * 100 << " %); mean error " << result.meanError
            << " (allowed " << tolerance.maxMeanError << "); max " << result.maxError;
  writeReport(folder, name, summary.str(), result.sizesMatch);
  ADD_FAILURE() << name << ": " << summary.str() << "\n  report: " << (folder / "report.html").string()
                << "\n  new image:  " << (folder / "new.png").string()
                << "\n  reference:  " << (folder / "reference.png").string()
                << "\n  difference: " << (folder / "diff.png").string();
}

}  // namespace kurage::test
