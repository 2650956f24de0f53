#pragma once
// Messages of one packing among several running side by side
// (apps/parallel_packings.h): each line is written whole, under one lock,
// with the packing's tag after the command's prefix ("demfem calibrate:
// seed 10001: ..."), so that the lines of two packings neither interleave
// nor lose whose they are. Without a tag the stream is std::cerr itself.
#include <iostream>
#include <mutex>
#include <streambuf>
#include <string>
#include <utility>

namespace demfem::apps
{
  class TaggedLog
  {
  public:
    TaggedLog(std::string prefix, std::string tag)
        : buf_(std::move(prefix), std::move(tag))
        , os_(&buf_)
    {
    }
    std::ostream &stream() { return buf_.tag.empty() ? std::cerr : os_; }

  private:
    struct LineBuf : std::streambuf
    {
      std::string prefix, tag, line;
      LineBuf(std::string p, std::string t)
          : prefix(std::move(p))
          , tag(std::move(t))
      {
      }
      ~LineBuf() override
      {
        if (!line.empty())
          emit();
      }
      int_type overflow(const int_type c) override
      {
        if (traits_type::eq_int_type(c, traits_type::eof()))
          return traits_type::not_eof(c);
        line.push_back(traits_type::to_char_type(c));
        if (line.back() == '\n')
          emit();
        return c;
      }
      std::streamsize xsputn(const char *s, const std::streamsize n) override
      {
        for (std::streamsize i = 0; i < n; ++i)
          overflow(traits_type::to_int_type(s[i]));
        return n;
      }
      void emit()
      {
        std::string out = line.compare(0, prefix.size(), prefix) == 0
                              ? prefix + tag + line.substr(prefix.size())
                              : tag + line;
        if (out.back() != '\n')
          out.push_back('\n');
        static std::mutex                 m;
        const std::lock_guard<std::mutex> lock(m);
        std::cerr.write(out.data(), std::streamsize(out.size()));
        std::cerr.flush();
        line.clear();
      }
    };
    LineBuf      buf_;
    std::ostream os_;
  };
} // namespace demfem::apps
