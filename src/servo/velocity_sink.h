// Where velocity commands go: a printed line per command, or a UDP datagram per command
// holding one JSON line {"t":<seconds>,"v":<m/s>,"w":<rad/s>} for a ROS bridge that
// republishes it on cmd_vel (geometry_msgs/Twist: linear.x = v, angular.z = w).
//
// Thread safety: none; one thread sends.
#pragma once

#include <memory>
#include <ostream>
#include <string>

#include "core/time.h"
#include "servo/unicycle.h"

namespace plslam {

class VelocitySink {
 public:
  virtual ~VelocitySink() = default;
  /// Sends one command stamped t_ns. Throws IoError when it cannot be delivered.
  virtual void send(TimeNs t_ns, const VelocityCommand& command) = 0;
  virtual std::string name() const = 0;
};

/// The JSON line of one command (no newline): {"t":12.345678,"v":0.1,"w":-0.25}.
std::string commandJson(TimeNs t_ns, const VelocityCommand& command);

/// Writes "t <seconds> v <m/s> w <rad/s>" lines to `out`.
class PrintSink : public VelocitySink {
 public:
  explicit PrintSink(std::ostream& out) : out_(out) {}
  void send(TimeNs t_ns, const VelocityCommand& command) override;
  std::string name() const override { return "print"; }

 private:
  std::ostream& out_;
};

/// Sends each command as a UDP datagram (commandJson + "\n") to host:port.
class UdpSink : public VelocitySink {
 public:
  /// Resolves `host` (name or IPv4/IPv6 address); throws ConfigError when it cannot, or
  /// when the port is out of range.
  UdpSink(const std::string& host, int port);
  ~UdpSink() override;
  UdpSink(const UdpSink&) = delete;
  UdpSink& operator=(const UdpSink&) = delete;
  void send(TimeNs t_ns, const VelocityCommand& command) override;
  std::string name() const override { return name_; }

 private:
  int fd_ = -1;
  std::string name_;
  std::string address_;  // the resolved sockaddr, as bytes
};

/// "print" (to `print_to`) or "udp:HOST:PORT". Throws ConfigError for anything else.
std::unique_ptr<VelocitySink> makeVelocitySink(const std::string& spec, std::ostream& print_to);

}  // namespace plslam
