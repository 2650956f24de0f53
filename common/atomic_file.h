#pragma once
// Every output file is replaced atomically (docs/architecture.md, "Outputs and
// run status"): written to `path.tmp` in the same directory, then renamed
// over `path`. A kill or a full disk leaves the last complete file, never a
// torn one, and one error naming the file and the reason. Header-only and
// standard C++ only, so that every layer (dem/, fem/, coupling/, apps/) may
// use it without depending on another.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace demfem
{
  inline void write_file_atomically(const std::string &path, const std::string &text)
  {
    const std::string tmp = path + ".tmp";
    {
      std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
      f << text;
      f.flush();
      if (!f)
        {
          const int error = errno;
          f.close();
          std::remove(tmp.c_str());
          throw std::runtime_error(
              "cannot write " + path +
              (error ? std::string(": ") + std::strerror(error) : ""));
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
      {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write " + path + ": " + ec.message());
      }
  }
} // namespace demfem
