#pragma once
// Named state of the objects around a DEM model (the coupling, the tunnel
// workflow) for checkpoints (docs/architecture.md, "Checkpoints and
// restart"). Each object has one function, `serialize(StateArchive &)`,
// used for both saving and loading, so the two cannot drift apart; every
// entry becomes a named, checksummed dataset /state/<name> of the checkpoint
// (dem/io/checkpoint.h), as the model's own state does.
#include "dem/engine/types.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace demfem::dem
{
  using NamedArrays = std::map<std::string, std::vector<double>>;

  class StateArchive
  {
  public:
    static StateArchive saving(NamedArrays &arrays) { return {&arrays, nullptr, ""}; }
    /// `file` names the checkpoint in errors.
    static StateArchive loading(const NamedArrays &arrays, const std::string &file)
    {
      return {nullptr, &arrays, file};
    }
    bool loading() const { return in_ != nullptr; }

    void io(const std::string &name, double &x)
    {
      if (out_)
        (*out_)[name] = {x};
      else
        x = entry(name, 1)[0];
    }

    /// Integers and flags, stored as doubles (exact up to 2^53, checked).
    template <class Int, std::enable_if_t<std::is_integral_v<Int>, int> = 0>
    void io(const std::string &name, Int &x)
    {
      if (out_)
        {
          (*out_)[name] = {static_cast<double>(x)};
          return;
        }
      const double v = entry(name, 1)[0];
      if (!(v == std::trunc(v) && std::abs(v) <= 9007199254740992.0) ||
          v < static_cast<double>(std::numeric_limits<Int>::lowest()) ||
          v > static_cast<double>(std::numeric_limits<Int>::max()))
        fail(name, "is not an integer of its type");
      x = static_cast<Int>(v);
    }

    /// Fixed-size Eigen matrices (vectors, tensors), column by column.
    template <int rows, int cols>
    void io(const std::string &name, Eigen::Matrix<double, rows, cols> &m)
    {
      if (out_)
        (*out_)[name] = std::vector<double>(m.data(), m.data() + rows * cols);
      else
        {
          const auto &v = entry(name, rows * cols);
          std::copy(v.begin(), v.end(), m.data());
        }
    }

    /// A vector of values; on loading its length must be `expected` unless
    /// that is `any_size`.
    static constexpr std::size_t any_size = std::size_t(-1);
    void                         io(const std::string &name, std::vector<double> &v,
                                    std::size_t expected = any_size)
    {
      if (out_)
        (*out_)[name] = v;
      else
        v = entry(name, expected);
    }

    /// A vector of fixed-size Eigen vectors (rows x n values).
    template <int n>
    void io(const std::string &name, std::vector<Eigen::Matrix<double, n, 1>> &v,
            std::size_t expected = any_size)
    {
      if (out_)
        {
          auto &a = (*out_)[name];
          a.clear();
          for (const auto &x : v)
            a.insert(a.end(), x.data(), x.data() + n);
          return;
        }
      const auto &a = entry(name, expected == any_size ? any_size : n * expected);
      if (a.size() % n != 0)
        fail(name, "has " + std::to_string(a.size()) + " values, not a multiple of " +
                       std::to_string(n));
      v.resize(a.size() / n);
      for (std::size_t i = 0; i < v.size(); ++i)
        for (int c = 0; c < n; ++c)
          v[i][c] = a[n * i + c];
    }

  private:
    StateArchive(NamedArrays *out, const NamedArrays *in, std::string file)
        : out_(out)
        , in_(in)
        , file_(std::move(file))
    {
    }

    const std::vector<double> &entry(const std::string &name, std::size_t size) const
    {
      const auto it = in_->find(name);
      if (it == in_->end())
        fail(name, "is missing (written by another program version?)");
      if (size != any_size && it->second.size() != size)
        fail(name, "has " + std::to_string(it->second.size()) + " values, expected " +
                       std::to_string(size) +
                       " (the model differs from the checkpointed one)");
      return it->second;
    }

    [[noreturn]] void fail(const std::string &name, const std::string &what) const
    {
      throw InputError("checkpoint " + file_ + ": state entry '" + name + "' " + what);
    }

    NamedArrays       *out_;
    const NamedArrays *in_;
    std::string        file_;
  };
} // namespace demfem::dem
