#pragma once
// What the laws made of the linear law plus a bond share (contact bond,
// parallel bond; docs/architecture.md, "Contact laws"): the linear part is
// LinearLaw on the first block of the law's state (Law::s_lin), so that the
// unbonded behaviour cannot drift from the plain linear law. The contact is
// active while bonded or while its linear part is, deletable only when
// unbonded and deletable as a linear contact, and its slip energy is the
// linear part's. Law provides bonded(st) and s_lin; Props has `linear`.
namespace demfem::dem
{
  template <class Law, class Linear>
  struct LinearWithBond
  {
    /// The linear law has no group-wide parameter (its Params is empty).
    static const typename Linear::Params &linear_group()
    {
      static const typename Linear::Params none{};
      return none;
    }

    template <class Params, class Props>
    static bool active(const Params &, const Props &q, const double *st, double gap)
    {
      return Law::bonded(st) ||
             Linear::active(linear_group(), q.linear, st + Law::s_lin, gap);
    }

    template <class Params, class Props>
    static bool deletable(const Params &, const Props &q, const double *st, double gap)
    {
      return !Law::bonded(st) &&
             Linear::deletable(linear_group(), q.linear, st + Law::s_lin, gap);
    }

    template <class Params, class Props>
    static double slip_energy(const Params &, const Props &q, const double *st)
    {
      return Linear::slip_energy(linear_group(), q.linear, st + Law::s_lin);
    }
  };
} // namespace demfem::dem
