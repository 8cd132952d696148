// HalfSpace's FFT state: the engine of the chosen precision and, while the kernels are built,
// their double spectra. Internal to src/elastic (half_space.cpp, half_space_kernels.cpp).
#pragma once

#include <memory>
#include <variant>
#include <vector>

#include "fft_engine.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "mpi_engine.hpp"

namespace fretbem {

using fft_detail::Engine;

// The engine of the chosen precision. Kernels are always built with a double engine (exact
// spectra); a float32 HalfSpace then swaps it for a float engine.
struct HalfSpace::Fft {
  std::variant<std::unique_ptr<Engine<double>>, std::unique_ptr<Engine<float>>> engine;
  // The engine of a distributed grid (double only); null when serial.
  std::unique_ptr<fft_detail::MpiEngine> mpi;
  // Double spectra of the kernel build, dropped once the engine holds its own copies.
  std::vector<double> sz, sxx, syy, sxy, szx, szy;

  Engine<double>& builder() { return *std::get<0>(engine); }
  template <class F>
  void visit(F&& f) {
    if (mpi) return f(*mpi);
    std::visit([&](auto& e) { f(*e); }, engine);
  }

  // Spectrum of a real even kernel stored row-major in k (n0*n1): its real part, divided by n.
  // part = 1: the imaginary part, the spectrum of the odd part of the kernel (cross kernels).
  std::vector<double> spectrum_of(const double* k, int part = 0) {
    Engine<double>& E = builder();
    const std::size_t nr = std::size_t(E.n0) * E.n1;
    std::copy_n(k, nr, E.rin.get());
    E.r2c(E.c1.get());
    std::fill(E.rin.get(), E.rin.get() + nr, 0.0);
    std::vector<double> s(std::size_t(E.n0) * E.nc);
    const double inv_n = 1.0 / (double(E.n0) * E.n1);
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = E.c1[i][part] * inv_n;
    return s;
  }
};

}  // namespace fretbem
