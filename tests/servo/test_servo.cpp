// The servo controllers in closed loop on ViSP's simulated unicycle: goal poses reached
// within 2 cm and 2 degrees with the pose errors of a real (synthetic) SLAM run, every
// command within the Burger's limits; the AprilTag servo; the velocity sinks.
#include <arpa/inet.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include <visp3/core/vpMath.h>

#include "camera/camera_file.h"
#include "core/error.h"
#include "io/dataset.h"
#include "servo/simulation.h"
#include "support/test_support.h"
#include "synthetic_cache.h"
#include "system/system.h"

using namespace plslam;

namespace {

// The per-frame camera errors of a sequential SLAM run on the synthetic static scene.
const std::vector<SE3>& slamErrors() {
  static const std::vector<SE3> errors = [] {
    const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
    const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
    DatasetOptions dopt;
    dopt.max_frames = 30;
    TumDataset data = TumDataset::open(dir, camera, dopt);
    SystemOptions o;
    o.sequential = true;
    System slam(camera, o);
    slam.start();
    RgbdFrame frame;
    while (data.next(&frame)) slam.feed(frame);
    slam.finish();
    return SlamPoseError::cameraErrors(slam.trajectory(), data.groundtruth());
  }();
  return errors;
}

void expectWithinLimits(const SimulationResult& r, const UnicycleLimits& limits) {
  for (const VelocityCommand& c : r.commands) {
    ASSERT_LE(std::abs(c.v), limits.v_max);
    ASSERT_LE(std::abs(c.w), limits.w_max);
  }
}

void printFigures(const char* what, const SimulationResult& r) {
  std::printf("[servo figures] %s: %s, %d iterations, %.2f s simulated, final error %.2f cm %.2f deg, max |v| %.3f "
              "max |w| %.3f\n",
              what, r.converged ? "converged" : "NOT converged", r.iterations, r.sim_time_s, 100 * r.position_error,
              vpMath::deg(std::abs(r.yaw_error)), r.max_abs_v, r.max_abs_w);
}

}  // namespace

TEST(Unicycle, SaturationKeepsTheRatioAndTheLimits) {
  const UnicycleLimits limits;
  const VelocityCommand c = saturate({0.44, 1.0}, limits);
  EXPECT_NEAR(c.v, 0.22, 1e-12);
  EXPECT_NEAR(c.w, 0.5, 1e-12) << "w scaled by the same factor as v";
  const VelocityCommand d = saturate({0.1, -5.68}, limits);
  EXPECT_NEAR(d.w, -2.84, 1e-12);
  EXPECT_NEAR(d.v, 0.05, 1e-12);
  const VelocityCommand e = saturate({0.1, 1.0}, limits);
  EXPECT_EQ(e.v, 0.1);
  EXPECT_EQ(e.w, 1.0);
}

TEST(Unicycle, PlanarMapAnchorsThePlaneAtTheFirstBasePose) {
  const vpHomogeneousMatrix bMc = PlanarMap::defaultCameraMounting();
  // The SLAM map is the first camera frame: its pose is the identity.
  const PlanarMap map = PlanarMap::anchorAtFirstPose(vpHomogeneousMatrix(), bMc);
  const PlanarPose at_start = PlanarMap::planar(map.baseInPlane(vpHomogeneousMatrix()));
  EXPECT_NEAR(at_start.x, 0, 1e-12);
  EXPECT_NEAR(at_start.y, 0, 1e-12);
  EXPECT_NEAR(at_start.yaw, 0, 1e-12);
  // Moving the base 1 m forward moves the camera 1 m along its optical axis.
  const vpHomogeneousMatrix wMc(vpTranslationVector(0, 0, 1), vpRotationMatrix());
  const PlanarPose ahead = PlanarMap::planar(map.baseInPlane(wMc));
  EXPECT_NEAR(ahead.x, 1, 1e-12);
  EXPECT_NEAR(ahead.y, 0, 1e-12);
}

TEST(PoseServo, ReachesGoalsWithSlamPoseErrorsWithinTwoCentimetresAndTwoDegrees) {
  const std::vector<SE3>& errors = slamErrors();
  double max_t = 0, max_r = 0;
  SlamPoseError::magnitude(errors, &max_t, &max_r);
  ASSERT_GT(max_t, 0) << "the SLAM run should have some error to apply";
  std::printf("[servo figures] SLAM pose errors: %zu frames, up to %.2f mm %.3f deg\n", errors.size(), 1000 * max_t,
              vpMath::deg(max_r));
  const PoseServoOptions options;
  struct Case {
    PlanarPose start, goal;
  };
  const Case cases[] = {
      {{0, 0, 0}, {1.5, 0.5, vpMath::rad(90)}},       // ahead, turn at the end
      {{0, 0, 0}, {-1.0, 0.3, vpMath::rad(-120)}},    // behind: turn first
      {{0.5, -0.2, 2.0}, {0.3, -0.8, vpMath::rad(180)}},
      {{0, 0, 0}, {0.0, 0.0, vpMath::rad(135)}},      // rotation only
  };
  for (const Case& c : cases) {
    SlamPoseError model(errors);
    SimulationOptions sim;
    sim.start = c.start;
    const SimulationResult r = simulatePoseServo(c.goal, options, sim, &model);
    printFigures("goal", r);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(r.position_error, 0.02) << "goal " << c.goal.x << "," << c.goal.y;
    EXPECT_LT(vpMath::deg(std::abs(r.yaw_error)), 2.0) << "goal " << c.goal.x << "," << c.goal.y;
    expectWithinLimits(r, options.limits);
  }
}

TEST(PoseServo, ConvergesUnderGaussianPoseNoise) {
  const PoseServoOptions options;
  GaussianPoseError noise(0.003, vpMath::rad(0.2), 7);
  SimulationOptions sim;
  const SimulationResult r = simulatePoseServo({2.0, -1.0, vpMath::rad(-45)}, options, sim, &noise);
  printFigures("goal with noise", r);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.position_error, 0.02);
  EXPECT_LT(vpMath::deg(std::abs(r.yaw_error)), 2.0);
  expectWithinLimits(r, options.limits);
}

// A pose model with no pose for the first steps (SLAM not tracking yet): the base waits, then goes.
TEST(PoseServo, StandsStillWhileThereIsNoPoseThenConverges) {
  class LateStart : public PoseErrorModel {
   public:
    std::optional<vpHomogeneousMatrix> measure(int step, const vpHomogeneousMatrix& wMc_true) override {
      if (step < 10) return std::nullopt;
      return wMc_true;
    }
  } model;
  const SimulationResult r = simulatePoseServo({1.0, 0.0, 0.0}, PoseServoOptions(), SimulationOptions(), &model);
  EXPECT_EQ(r.blind_steps, 10);
  ASSERT_GT(r.commands.size(), 10u);
  for (int k = 0; k < 10; ++k) EXPECT_TRUE(r.commands[k].v == 0 && r.commands[k].w == 0) << "step " << k;
  EXPECT_GT(r.commands[10].v, 0);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.position_error, 0.02);
}

TEST(TagServo, StopsAtTheStandoffFacingTheTag) {
  TagServoOptions options;
  options.standoff = 0.6;
  SimulationOptions sim;
  sim.start = {0, 0, vpMath::rad(20)};
  const vpHomogeneousMatrix pMo(vpTranslationVector(2.0, 0.6, sim.bMc[2][3]), vpRotationMatrix());
  const SimulationResult r = simulateTagServo(pMo, options, sim);
  printFigures("tag", r);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(std::abs(r.position_error), 0.02) << "depth error";
  EXPECT_LT(vpMath::deg(std::abs(r.yaw_error)), 2.0) << "bearing of the tag";
  expectWithinLimits(r, options.limits);
  // The camera stands `standoff` from the tag centre.
  const double cx = r.final_pose.x + sim.bMc[0][3] * std::cos(r.final_pose.yaw);
  const double cy = r.final_pose.y + sim.bMc[0][3] * std::sin(r.final_pose.yaw);
  EXPECT_NEAR(std::hypot(2.0 - cx, 0.6 - cy), 0.6, 0.02);
}

TEST(VelocitySink, PrintSinkWritesOneLinePerCommand) {
  std::ostringstream out;
  const auto sink = makeVelocitySink("print", out);
  sink->send(secondsToNs(1.5), {0.1, -0.25});
  sink->send(secondsToNs(1.6), {0.0, 0.5});
  EXPECT_EQ(out.str(), "t 1.500000 v +0.1000 w -0.2500\nt 1.600000 v +0.0000 w +0.5000\n");
}

TEST(VelocitySink, UdpSinkSendsOneJsonLinePerCommand) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  socklen_t len = sizeof(addr);
  ASSERT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  timeval timeout{2, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  std::ostringstream unused;
  const auto sink = makeVelocitySink("udp:127.0.0.1:" + std::to_string(ntohs(addr.sin_port)), unused);
  const VelocityCommand sent[] = {{0.12, -0.5}, {0.0, 2.84}, {-0.22, 0.0}};
  for (int i = 0; i < 3; ++i) sink->send(secondsToNs(10.0 + i / 30.0), sent[i]);
  for (int i = 0; i < 3; ++i) {
    char buffer[512];
    const ssize_t n = ::recv(fd, buffer, sizeof(buffer) - 1, 0);
    ASSERT_GT(n, 0) << "datagram " << i << " not received";
    buffer[n] = '\0';
    const std::string line(buffer);
    ASSERT_EQ(line.back(), '\n') << "one JSON line per datagram";
    EXPECT_EQ(line.find('\n'), line.size() - 1) << "one line";
    const nlohmann::json j = test::parseJson(line, "datagram");
    ASSERT_TRUE(j.is_object()) << line;
    EXPECT_NEAR(j.at("t").get<double>(), 10.0 + i / 30.0, 1e-6);
    EXPECT_NEAR(j.at("v").get<double>(), sent[i].v, 1e-9);
    EXPECT_NEAR(j.at("w").get<double>(), sent[i].w, 1e-9);
  }
  ::close(fd);
}

TEST(VelocitySink, BadSpecificationsAreRefused) {
  std::ostringstream out;
  for (const char* spec : {"", "udp", "udp:host", "udp::9000", "udp:localhost:x", "udp:localhost:70000", "tcp:a:1"})
    EXPECT_THROW(makeVelocitySink(spec, out), ConfigError) << spec;
}

TEST(ServoCli, SimulatedGoalConvergesAndTheRealRobotPathSaysWhatIsMissing) {
  auto r = test::runPlslam("servo --simulate --goal 1,0.5,90 --noise-position 0.002 --noise-rotation 0.1 --sink print");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("goal servo converged"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\nt "), std::string::npos) << "printed commands";
  r = test::runPlslam("servo --goal 1,0.5,90");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--simulate"), std::string::npos) << r.output;
}

// plslam servo --base: the measured mounting replaces the placeholder. A camera 0.30 m ahead
// of the wheel axis (the placeholder: 0.10 m) stops the base 0.20 m farther from the tag.
TEST(ServoCli, BaseFileMountingMovesWhereTheBaseStops) {
  const std::string dir = test::scratchDir("servo_base");
  std::ofstream(dir + "/base.yaml") << "format: plslam_camera_to_base 1\nparent_frame: base\nchild_frame: camera\n"
                                       "translation: [0.30, 0, 0.15]\nrotation: [-0.5, 0.5, -0.5, 0.5]\n";
  auto finalX = [](const std::string& output) {
    const size_t at = output.find("final base pose ");
    return at == std::string::npos ? -1.0 : std::atof(output.c_str() + at + 16);
  };
  const std::string tag = "servo --simulate --tag 2,0 --standoff 0.5 --sink udp:127.0.0.1:9";
  const auto placeholder = test::runPlslam(tag);
  ASSERT_EQ(placeholder.status, 0) << placeholder.output;
  const auto measured = test::runPlslam(tag + " --base " + dir + "/base.yaml");
  ASSERT_EQ(measured.status, 0) << measured.output;
  EXPECT_NEAR(finalX(placeholder.output), 2.0 - 0.5 - 0.10, 0.02) << placeholder.output;
  EXPECT_NEAR(finalX(measured.output), 2.0 - 0.5 - 0.30, 0.02) << measured.output;
}
