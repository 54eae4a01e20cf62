#include "servo/velocity_sink.h"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "core/json.h"
#include "core/log.h"

namespace plslam {

std::string commandJson(TimeNs t_ns, const VelocityCommand& command) {
  const Json line = {{"t", nsToSeconds(t_ns)}, {"v", command.v}, {"w", command.w}};
  return line.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void PrintSink::send(TimeNs t_ns, const VelocityCommand& command) {
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), "t %s v %+.4f w %+.4f\n", formatSecondsStamp(t_ns).c_str(), command.v, command.w);
  out_ << buffer;
  out_.flush();
}

UdpSink::UdpSink(const std::string& host, int port) : name_(str("udp:", host, ":", port)) {
  if (port <= 0 || port > 65535) throw ConfigError(str("UDP sink: port ", port, " out of range (1-65535)"));
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
  if (rc != 0 || !found) throw ConfigError("UDP sink: cannot resolve host '" + host + "': " + ::gai_strerror(rc));
  fd_ = ::socket(found->ai_family, found->ai_socktype, found->ai_protocol);
  if (fd_ < 0) {
    ::freeaddrinfo(found);
    throw IoError(std::string("UDP sink: cannot create a socket: ") + std::strerror(errno));
  }
  address_.assign(reinterpret_cast<const char*>(found->ai_addr), found->ai_addrlen);
  ::freeaddrinfo(found);
}

UdpSink::~UdpSink() {
  if (fd_ >= 0) ::close(fd_);
}

void UdpSink::send(TimeNs t_ns, const VelocityCommand& command) {
  const std::string line = commandJson(t_ns, command) + "\n";
  const ssize_t n = ::sendto(fd_, line.data(), line.size(), 0, reinterpret_cast<const sockaddr*>(address_.data()),
                             static_cast<socklen_t>(address_.size()));
  if (n != static_cast<ssize_t>(line.size()))
    throw IoError(name_ + ": cannot send a command: " + (n < 0 ? std::strerror(errno) : "short write"));
}

std::unique_ptr<VelocitySink> makeVelocitySink(const std::string& spec, std::ostream& print_to) {
  if (spec == "print") return std::make_unique<PrintSink>(print_to);
  if (spec.rfind("udp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const size_t colon = rest.rfind(':');
    if (colon != std::string::npos && colon > 0) {
      std::string host = rest.substr(0, colon);
      if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
      const std::string port = rest.substr(colon + 1);
      char* end = nullptr;
      const long p = std::strtol(port.c_str(), &end, 10);
      if (!port.empty() && end && *end == '\0') return std::make_unique<UdpSink>(host, static_cast<int>(p));
    }
  }
  throw ConfigError("velocity sink '" + spec + "': expected print or udp:HOST:PORT");
}

}  // namespace plslam
