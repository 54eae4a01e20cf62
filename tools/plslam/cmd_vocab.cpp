// plslam vocab: train a bag-of-words vocabulary (ORB and LBD trees) on folders of images,
// or describe a vocabulary file.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "progress_line.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "frontend/feature_extraction.h"
#include "place/vocabulary.h"

namespace plslam::cli {

namespace {

namespace fs = std::filesystem;

std::vector<std::string> imagesOf(const std::string& dir) {
  fs::path root(dir);
  if (fs::is_directory(root / "rgb")) root /= "rgb";  // a TUM-layout folder
  if (!fs::is_directory(root)) throw IoError(dir + ": not a folder of images");
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(root)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  if (out.empty()) throw IoError(dir + ": no .png/.jpg images (nor in rgb/)");
  return out;
}

int runTrain(int argc, char** argv) {
  Args args("vocab train", "Train an ORB + LBD bag-of-words vocabulary (k-majority tree per descriptor type).");
  args.option("images", "image folders, comma-separated (a TUM folder's rgb/ is used)", "", true)
      .option("out", "vocabulary file to write", "", true)
      .option("k", "branching factor", "10")
      .option("levels", "tree depth", "4")
      .option("every", "use every N-th image of each folder", "1")
      .option("seed", "k-means++ seeding", "1")
      .epilog("Features are extracted with the default feature options of plslam run (ORB 1000, LSD/LBD 150).\n"
              "example: plslam vocab train --images data/a,data/b --out vocab/my.voc --k 10 --levels 4");
  if (!args.parse(argc, argv)) return 0;
  VocabularyTrainOptions o;
  o.k = args.integer("k", 2, 64);
  o.levels = args.integer("levels", 1, 8);
  o.seed = static_cast<uint64_t>(args.integer("seed", 0, 1 << 30));
  const int every = args.integer("every", 1, 100000);
  const FeatureOptions fo;
  std::vector<cv::Mat> orb, lbd;
  std::stringstream list(args.str("images"));
  for (std::string dir; std::getline(list, dir, ',');) {
    if (dir.empty()) continue;
    const std::vector<std::string> files = imagesOf(dir);
    ProgressLine line("vocab");
    for (size_t i = 0; i < files.size(); i += every) {
      const cv::Mat image = cv::imread(files[i], cv::IMREAD_COLOR);
      if (image.empty()) throw IoError(files[i] + ": cannot read the image");
      const cv::Mat grey = toGrey(image);
      std::vector<cv::KeyPoint> kps;
      cv::Mat d;
      extractOrb(grey, cv::Mat(), fo.orb, &kps, &d);
      orb.push_back(d);
      const std::vector<LineSegment2D> segs = detectLines(grey, cv::Mat(), fo.lines);
      lbd.push_back(describeLines(grey, segs, fo.lines));
      line.update("%s: image %zu/%zu", dir.c_str(), i + 1, files.size());
    }
    line.done();
  }
  VocabularySet v;
  v.orb = Vocabulary::train(orb, o);
  v.lbd = Vocabulary::train(lbd, o);
  saveVocabulary(args.str("out"), v);
  std::printf("trained on %zu images: ORB %d words, LBD %d words (k %d, levels %d); wrote %s\n", orb.size(),
              v.orb.words(), v.lbd.words(), o.k, o.levels, args.str("out").c_str());
  return 0;
}

int runInfo(int argc, char** argv) {
  Args args("vocab info", "Check and describe a vocabulary file.");
  args.option("file", "vocabulary file", "", true);
  if (!args.parse(argc, argv)) return 0;
  const VocabularySet v = loadVocabulary(args.str("file"));
  for (const auto& [name, t] : {std::make_pair("ORB", &v.orb), std::make_pair("LBD", &v.lbd)})
    std::printf("%s: %d words, k %d, levels %d, trained on %d images\n", name, t->words(), t->k(), t->levels(),
                t->trainingImages());
  return 0;
}

int runVocab(int argc, char** argv) {
  const std::string sub = argc > 0 ? argv[0] : "";
  if (sub == "train") return runTrain(argc - 1, argv + 1);
  if (sub == "info") return runInfo(argc - 1, argv + 1);
  if (sub == "--help" || sub == "-h" || sub.empty()) {
    std::cout << "usage: plslam vocab train --images DIR[,DIR...] --out FILE [--k 10 --levels 4]\n"
                 "       plslam vocab info --file FILE\n";
    return sub.empty() ? 2 : 0;
  }
  throw ConfigError("plslam vocab: unknown sub-command '" + sub + "' (train, info)");
}

}  // namespace

Command makeVocabCommand() { return {"vocab", "train or check a bag-of-words vocabulary (loop closure)", runVocab}; }

}  // namespace plslam::cli
