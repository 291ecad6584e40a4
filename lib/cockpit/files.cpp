#include "cockpit/files.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tiller::cockpit {

namespace fs = std::filesystem;

std::string load_or_create_token(const std::string& path) {
  if (sodium_init() < 0) throw std::runtime_error("libsodium failed to initialise");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::exists(parent)) {
      fs::create_directories(parent);
      fs::permissions(parent, fs::perms::owner_all);
    }
    unsigned char raw[32];
    randombytes_buf(raw, sizeof raw);
    char hex[65];
    sodium_bin2hex(hex, sizeof hex, raw, sizeof raw);
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0)
      throw std::runtime_error("token file " + path + ": cannot create: " + std::strerror(errno));
    const std::string line = std::string(hex) + "\n";
    const bool ok = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
    ::close(fd);
    if (!ok) throw std::runtime_error("token file " + path + ": cannot write");
    return hex;
  }
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    throw std::runtime_error("token file " + path + ": readable by group or others; chmod 600 " +
                             path);
  }
  std::ifstream in(path);
  std::string token;
  std::getline(in, token);
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  if (token.size() < 16)
    throw std::runtime_error("token file " + path + ": expected a token of at least 16 characters");
  return token;
}

mission::Mission load_mission_text(const std::string& name, const std::string& text,
                                   const std::optional<mission::GeoPoint>& datum) {
  const std::string base = fs::path(name).filename().string();
  const std::string ext = fs::path(base).extension().string();
  if (base.empty() || (ext != ".yaml" && ext != ".yml" && ext != ".csv" && ext != ".plan"))
    throw std::runtime_error(name + ": expected a .yaml, .yml, .csv or .plan mission file");
  for (char c : base) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_'))
      throw std::runtime_error(name + ": a file name of letters, digits, '.', '-' and '_' only");
  }
  std::string dir_template = (fs::temp_directory_path() / "tiller-cockpit-XXXXXX").string();
  if (::mkdtemp(dir_template.data()) == nullptr)
    throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
  const std::string dir = dir_template;
  const std::string file = dir + "/" + base;
  {
    std::ofstream out(file, std::ios::binary);
    out << text;
  }
  auto cleanup = [&] {
    std::error_code ec;
    fs::remove_all(dir, ec);
  };
  try {
    mission::Mission m = mission::load_mission_file(file, datum);
    cleanup();
    return m;
  } catch (const std::exception& e) {
    cleanup();
    std::string msg = e.what();
    for (auto at = msg.find(dir + "/"); at != std::string::npos; at = msg.find(dir + "/"))
      msg.erase(at, dir.size() + 1);  // name the upload, not the temporary copy
    throw std::runtime_error(msg);
  }
}

}  // namespace tiller::cockpit
