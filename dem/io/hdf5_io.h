#pragma once
// Thin RAII layer over the HDF5 C API used by the DEM checkpoints
// (dem/io/checkpoint.cc): datasets of fixed-size rows, scalars, string lists,
// and atomic file replacement (docs/architecture.md, "Checkpoints and
// restart": write a new name, fsync, rename over the old file, keep the
// previous one). Internal to dem/: it includes
// hdf5.h (OpenMPI flavour, see dem/CMakeLists.txt).
//
// Integrity: every non-empty dataset is chunked with the Fletcher32 checksum
// filter, strings included (stored as bytes, since a variable-length
// string's characters live outside the dataset and the filter would not
// cover them), and the whole file ends with a checksum trailer (below,
// "Whole-file checksum and writing"). A damaged byte in a dataset makes
// H5Dread fail; read_data reports it naming the dataset and the file.
#include "dem/engine/types.h"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace demfem::dem::hdf5io
{
  /// Where errors go: writing errors are I/O failures (runtime_error),
  /// reading errors are bad input (InputError); both name the file.
  struct Ctx
  {
    std::string       file;
    bool              reading;
    [[noreturn]] void fail(const std::string &what) const
    {
      const std::string msg = "checkpoint " + file + ": " + what;
      if (reading)
        throw InputError(msg);
      throw std::runtime_error(msg);
    }
  };

  /// Owns one HDF5 identifier.
  class Handle
  {
  public:
    Handle(hid_t id, herr_t (*close)(hid_t))
        : id_(id)
        , close_(close)
    {
    }
    Handle(Handle &&o) noexcept
        : id_(o.id_)
        , close_(o.close_)
    {
      o.id_ = -1;
    }
    Handle(const Handle &)            = delete;
    Handle &operator=(const Handle &) = delete;
    ~Handle()
    {
      if (id_ >= 0)
        close_(id_);
    }
           operator hid_t() const { return id_; }
    bool   valid() const { return id_ >= 0; }
    herr_t close()
    {
      const herr_t r = id_ >= 0 ? close_(id_) : 0;
      id_            = -1;
      return r;
    }

  private:
    hid_t id_;
    herr_t (*close_)(hid_t);
  };

  /// HDF5 prints its error stack to stderr by default; we report errors
  /// ourselves, naming the file and the dataset.
  struct QuietHdf5
  {
    H5E_auto2_t func = nullptr;
    void       *data = nullptr;
    QuietHdf5()
    {
      H5Eget_auto2(H5E_DEFAULT, &func, &data);
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func, data); }
  };

  template <class T>
  hid_t h5type()
  {
    if constexpr (std::is_same_v<T, double>)
      return H5T_NATIVE_DOUBLE;
    else if constexpr (std::is_same_v<T, int>)
      return H5T_NATIVE_INT;
    else if constexpr (std::is_same_v<T, std::uint32_t>)
      return H5T_NATIVE_UINT32;
    else if constexpr (std::is_same_v<T, std::int64_t>)
      return H5T_NATIVE_INT64;
    else if constexpr (std::is_same_v<T, std::uint8_t>)
      return H5T_NATIVE_UINT8;
    else
      {
        static_assert(std::is_same_v<T, char>, "unsupported checkpoint element type");
        return H5T_NATIVE_CHAR;
      }
  }

  inline Handle make_group(const Ctx &c, hid_t loc, const std::string &name)
  {
    Handle g(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Gclose);
    if (!g.valid())
      c.fail("cannot create group '" + name + "'");
    return g;
  }

  inline Handle open_group(const Ctx &c, hid_t loc, const std::string &name)
  {
    Handle g(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), H5Gclose);
    if (!g.valid())
      c.fail("missing group '" + name + "'");
    return g;
  }

  /// Dataset creation properties: chunked (the filter needs chunks; about
  /// 1 MiB each) with the Fletcher32 checksum. An empty dataset has no data
  /// to protect and keeps the default contiguous layout (a chunk cannot be
  /// larger than a fixed zero extent).
  inline Handle checksummed_layout(const Ctx &c, const std::string &name,
                                   std::size_t value_size, std::size_t rows,
                                   std::size_t cols)
  {
    Handle p(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    if (!p.valid())
      c.fail("cannot create the properties of dataset '" + name + "'");
    if (rows * cols == 0)
      return p;
    const std::size_t row_bytes = std::max<std::size_t>(1, cols * value_size);
    const hsize_t     chunk_rows =
        std::max<hsize_t>(1, std::min<hsize_t>(rows, (std::size_t(1) << 20) / row_bytes));
    const hsize_t chunk[2] = {chunk_rows, cols};
    if (H5Pset_chunk(p, cols == 1 ? 1 : 2, chunk) < 0 || H5Pset_fletcher32(p) < 0)
      c.fail("cannot set the checksum filter of dataset '" + name + "'");
    return p;
  }

  /// Whether the dataset `set` carries the Fletcher32 filter.
  inline bool has_checksum(hid_t set)
  {
    Handle       p(H5Dget_create_plist(set), H5Pclose);
    unsigned int flags = 0;
    std::size_t  n     = 0;
    char         name[16];
    const int    filters = p.valid() ? H5Pget_nfilters(p) : 0;
    for (int k = 0; k < filters; ++k)
      if (H5Pget_filter2(p, unsigned(k), &flags, &n, nullptr, sizeof name, name,
                         nullptr) == H5Z_FILTER_FLETCHER32)
        return true;
    return false;
  }

  /// Reads the whole dataset; a failure of a checksummed dataset is told
  /// apart by reading again without checksum verification: if that works,
  /// the stored bytes no longer match their checksum.
  inline void read_checked(const Ctx &c, hid_t set, hid_t type,
                           const std::string &short_name, void *out)
  {
    char              path[512] = {};
    const std::string name =
        H5Iget_name(set, path, sizeof path) > 0 ? std::string(path) : short_name;
    if (H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0)
      return;
    if (has_checksum(set))
      {
        Handle x(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
        if (x.valid() && H5Pset_edc_check(x, H5Z_DISABLE_EDC) >= 0 &&
            H5Dread(set, type, H5S_ALL, H5S_ALL, x, out) >= 0)
          c.fail("dataset '" + name +
                 "' fails its Fletcher32 checksum: the file is damaged (use the "
                 "previous checkpoint, checkpoint.h5.prev, or start again)");
        c.fail("dataset '" + name + "' cannot be read (damaged file?)");
      }
    c.fail("cannot read dataset '" + name + "'");
  }

  /// Writes rows x cols values of T (1D dataset when cols == 1).
  template <class T>
  void write_data(const Ctx &c, hid_t loc, const std::string &name, const void *data,
                  std::size_t rows, std::size_t cols)
  {
    const hsize_t dims[2] = {rows, cols};
    Handle        space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose);
    Handle        create = checksummed_layout(c, name, sizeof(T), rows, cols);
    Handle set(H5Dcreate2(loc, name.c_str(), h5type<T>(), space, H5P_DEFAULT, create,
                          H5P_DEFAULT),
               H5Dclose);
    if (!space.valid() || !set.valid())
      c.fail("cannot create dataset '" + name + "'");
    if (rows * cols > 0 &&
        H5Dwrite(set, h5type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      c.fail("cannot write dataset '" + name + "'");
  }

  /// Reads a dataset written by write_data into `out` (rows * cols values
  /// of T, stored as E); checks the shape; returns the number of rows.
  template <class T, class E>
  std::size_t read_data(const Ctx &c, hid_t loc, const std::string &name,
                        std::vector<E> &out, std::size_t cols)
  {
    static_assert(sizeof(E) % sizeof(T) == 0, "element is not made of T");
    const std::size_t per = sizeof(E) / sizeof(T); // values per element
    Handle            set(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid())
      c.fail("missing dataset '" + name + "'");
    Handle    space(H5Dget_space(set), H5Sclose);
    hsize_t   dims[2] = {0, 1};
    const int rank    = H5Sget_simple_extent_ndims(space);
    if (rank != (cols == 1 ? 1 : 2) ||
        H5Sget_simple_extent_dims(space, dims, nullptr) < 0 || dims[1] != cols ||
        (dims[0] * cols) % per != 0)
      {
        std::ostringstream msg;
        msg << "dataset '" << name << "' has the wrong shape (expected " << cols
            << " value(s) per row)";
        c.fail(msg.str());
      }
    out.resize(dims[0] * cols / per);
    if (!out.empty())
      read_checked(c, set, h5type<T>(), name, out.data());
    return dims[0];
  }

  /// Rows of fixed-size elements (Eigen vectors, arrays, ContactForce) as
  /// rows x (sizeof(E) / sizeof(T)) datasets.
  template <class T, class E>
  void write_rows(const Ctx &c, hid_t loc, const std::string &name,
                  const std::vector<E> &v)
  {
    static_assert(sizeof(E) % sizeof(T) == 0, "element is not made of T");
    write_data<T>(c, loc, name, v.data(), v.size(), sizeof(E) / sizeof(T));
  }

  template <class T, class E>
  void read_rows(const Ctx &c, hid_t loc, const std::string &name, std::vector<E> &v,
                 std::size_t expected_rows)
  {
    read_data<T>(c, loc, name, v, sizeof(E) / sizeof(T));
    if (v.size() != expected_rows)
      c.fail("dataset '" + name + "' has " + std::to_string(v.size()) +
             " rows, expected " + std::to_string(expected_rows));
  }

  template <class T>
  void write_scalar(const Ctx &c, hid_t loc, const std::string &name, T value)
  {
    write_data<T>(c, loc, name, &value, 1, 1);
  }

  template <class T>
  T read_scalar(const Ctx &c, hid_t loc, const std::string &name)
  {
    std::vector<T> v;
    read_data<T>(c, loc, name, v, 1);
    if (v.size() != 1)
      c.fail("dataset '" + name + "' is not a scalar");
    return v[0];
  }

  inline Handle string_type()
  {
    Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);
    return t;
  }

  /// A list of strings as two checksummed datasets: `name` holds the bytes
  /// of all strings one after the other, `name_lengths` their lengths.
  inline void write_strings(const Ctx &c, hid_t loc, const std::string &name,
                            const std::vector<std::string> &s)
  {
    std::string               bytes;
    std::vector<std::int64_t> lengths;
    for (const auto &x : s)
      bytes += x, lengths.push_back(std::int64_t(x.size()));
    write_data<char>(c, loc, name, bytes.data(), bytes.size(), 1);
    write_data<std::int64_t>(c, loc, name + "_lengths", lengths.data(), lengths.size(),
                             1);
  }

  inline std::vector<std::string> read_strings(const Ctx &c, hid_t loc,
                                               const std::string &name)
  {
    {
      Handle set(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
      if (!set.valid())
        c.fail("missing dataset '" + name + "'");
      Handle type(H5Dget_type(set), H5Tclose);
      if (type.valid() && H5Tis_variable_str(type) > 0)
        {
          // Written by a version before the checksums (format <= 3): read
          // as such, so that the version check names the format.
          Handle  vtype = string_type();
          Handle  space(H5Dget_space(set), H5Sclose);
          hsize_t n = 0;
          if (H5Sget_simple_extent_ndims(space) != 1 ||
              H5Sget_simple_extent_dims(space, &n, nullptr) < 0)
            c.fail("dataset '" + name + "' is not a list of strings");
          std::vector<char *> p(n, nullptr);
          if (n > 0 && H5Dread(set, vtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()) < 0)
            c.fail("cannot read dataset '" + name + "' as strings");
          std::vector<std::string> out;
          for (char *x : p)
            out.emplace_back(x ? x : "");
          if (n > 0)
            H5Dvlen_reclaim(vtype, space, H5P_DEFAULT, p.data());
          return out;
        }
    }
    std::vector<char>         bytes;
    std::vector<std::int64_t> lengths;
    read_data<char>(c, loc, name, bytes, 1);
    read_data<std::int64_t>(c, loc, name + "_lengths", lengths, 1);
    std::vector<std::string> out;
    std::size_t              at = 0;
    for (const auto n : lengths)
      {
        if (n < 0 || at + std::size_t(n) > bytes.size())
          c.fail("dataset '" + name + "_lengths' does not match '" + name + "'");
        out.emplace_back(bytes.data() + at, std::size_t(n));
        at += std::size_t(n);
      }
    if (at != bytes.size())
      c.fail("dataset '" + name + "_lengths' does not match '" + name + "'");
    return out;
  }

  // ----------------------------------------------------------------------
  // Atomic file replacement (docs/architecture.md, "Checkpoints and restart").

  inline void fsync_path(const std::string &p, bool directory, const Ctx &c)
  {
    const int fd = ::open(p.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
    if (fd < 0)
      c.fail("cannot open " + p + " to sync it: " + std::strerror(errno));
    const int r = ::fsync(fd), e = errno;
    ::close(fd);
    if (r != 0 && !directory) // some file systems cannot sync directories
      c.fail("fsync of " + p + " failed: " + std::strerror(e));
  }

  inline std::string directory_of(const std::string &path)
  {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  }

  // ----------------------------------------------------------------------
  // Whole-file checksum and writing. The dataset checksums do not cover
  // HDF5's own structures between them (object headers, chunk indexes,
  // heaps, free space of its block aggregation: about half of a small
  // checkpoint, measured), so the file ends with a trailer holding a
  // checksum of all the bytes before it (HDF5 ignores bytes past its end of
  // file). HDF5 builds the file in memory (core driver, no backing store)
  // and we write the bytes ourselves: a full disk is then our own write
  // error, reported with errno, and never an HDF5 file left half closed
  // (HDF5 1.10 crashes at exit on a file whose close failed).

  constexpr std::size_t trailer_size   = 64;
  constexpr const char *checksum_magic = "demfem-checksum fnv1a64 ";

  /// FNV-1a (64 bit) of `n` bytes.
  inline std::uint64_t fnv1a(const char *data, std::size_t n,
                             std::uint64_t h = 1469598103934665603ull)
  {
    for (std::size_t k = 0; k < n; ++k)
      h = (h ^ static_cast<unsigned char>(data[k])) * 1099511628211ull;
    return h;
  }

  /// The trailer of an image of n bytes with checksum h: magic, hex
  /// checksum, byte count, padded to trailer_size.
  inline std::string checksum_trailer(std::uint64_t h, std::size_t n)
  {
    std::ostringstream s;
    s << checksum_magic << std::hex << h << std::dec << " " << n << "\n";
    std::string t = s.str();
    t.resize(trailer_size, ' ');
    t.back() = '\n';
    return t;
  }

  /// Compares the file with its checksum trailer: 1 equal, 0 it differs
  /// (damaged), -1 no trailer (a file of format version <= 3, or the
  /// trailer itself is damaged).
  inline int compare_checksum(const Ctx &c)
  {
    const int fd = ::open(c.file.c_str(), O_RDONLY);
    if (fd < 0)
      c.fail(std::string("cannot open: ") + std::strerror(errno));
    struct stat st;
    if (::fstat(fd, &st) != 0 || std::size_t(st.st_size) < trailer_size)
      {
        ::close(fd);
        return -1;
      }
    const std::size_t n = std::size_t(st.st_size) - trailer_size;
    char              tail[trailer_size];
    if (::pread(fd, tail, trailer_size, off_t(n)) != ssize_t(trailer_size))
      {
        ::close(fd);
        return -1;
      }
    const std::string  magic = checksum_magic;
    std::istringstream in(std::string(tail + magic.size(), trailer_size - magic.size()));
    std::uint64_t      stored   = 0;
    std::size_t        stored_n = 0;
    if (std::string(tail, magic.size()) != magic ||
        !(in >> std::hex >> stored >> std::dec >> stored_n))
      {
        ::close(fd);
        return -1;
      }
    std::uint64_t     h = 1469598103934665603ull;
    std::vector<char> buf(1 << 16);
    for (std::size_t at = 0; at < n;)
      {
        const ssize_t got =
            ::pread(fd, buf.data(), std::min(buf.size(), n - at), off_t(at));
        if (got <= 0)
          {
            ::close(fd);
            c.fail(std::string("cannot read: ") + std::strerror(errno));
          }
        h = fnv1a(buf.data(), std::size_t(got), h);
        at += std::size_t(got);
      }
    ::close(fd);
    return h == stored && n == stored_n ? 1 : 0;
  }

  /// Writes `bytes` to a new file `path` and syncs it; runtime_error naming
  /// the file and the reason (e.g. "No space left on device").
  inline void write_bytes(const Ctx &c, const std::string &path, const std::string &bytes)
  {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0)
      c.fail("cannot create " + path + ": " + std::strerror(errno) +
             " (directory missing or not writable?)");
    for (std::size_t at = 0; at < bytes.size();)
      {
        const ssize_t put = ::write(fd, bytes.data() + at, bytes.size() - at);
        if (put < 0 && errno == EINTR)
          continue;
        if (put <= 0)
          {
            const int e = errno;
            ::close(fd);
            c.fail("cannot write " + path + ": " + std::strerror(e));
          }
        at += std::size_t(put);
      }
    if (::fsync(fd) != 0 || ::close(fd) != 0)
      c.fail("cannot write " + path + ": " + std::strerror(errno));
  }

  inline void write_atomically(const std::string                             &path,
                               const std::function<void(hid_t, const Ctx &)> &body)
  {
    const Ctx         c{path, false};
    const std::string tmp = path + ".tmp", prev = path + ".prev";
    try
      {
        std::string image;
        {
          QuietHdf5 quiet;
          Handle    access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
          if (!access.valid() || H5Pset_fapl_core(access, 1 << 20, 0) < 0)
            c.fail("cannot set up the in-memory file of " + tmp);
          Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access),
                      H5Fclose);
          if (!file.valid())
            c.fail("cannot create the in-memory file of " + tmp);
          body(file, c);
          if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
            c.fail("cannot flush the in-memory file of " + tmp);
          const ssize_t n = H5Fget_file_image(file, nullptr, 0);
          if (n <= 0)
            c.fail("cannot take the image of " + tmp);
          image.resize(std::size_t(n));
          if (H5Fget_file_image(file, image.data(), image.size()) != n ||
              file.close() < 0)
            c.fail("cannot take the image of " + tmp);
        }
        image += checksum_trailer(fnv1a(image.data(), image.size()), image.size());
        write_bytes(c, tmp, image);
      }
    catch (...)
      {
        ::unlink(tmp.c_str()); // never a directory: unlink leaves those alone
        throw;
      }
    // Keep the previous checkpoint as .prev: a hard link keeps `path`
    // valid at every instant; file systems without links get a rename.
    struct stat st;
    if (::stat(path.c_str(), &st) == 0)
      {
        if (::unlink(prev.c_str()) != 0 && errno != ENOENT)
          c.fail("cannot remove the old " + prev + ": " + std::strerror(errno));
        if (::link(path.c_str(), prev.c_str()) != 0 &&
            ::rename(path.c_str(), prev.c_str()) != 0)
          c.fail("cannot keep the previous checkpoint as " + prev + ": " +
                 std::strerror(errno));
      }
    if (::rename(tmp.c_str(), path.c_str()) != 0)
      c.fail("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
    fsync_path(directory_of(path), true, c);
  }
} // namespace demfem::dem::hdf5io
