// Reading and validating each scenario section into its spec (README "Scenario files").
#pragma once

#include "fretbem/scenario/scenario.hpp"
#include "value_reader.hpp"

namespace fretbem::scenario_detail {

/// Every key of the INI text, checked against the key table; duplicates refused.
void read_file_entries(const std::string& text, Reader& r);
/// One `--set section.key=value`, which replaces the file's value.
void apply_override(const std::string& text, Reader& r);

void read_material(const Reader& r, Material& m);
void read_grid(const Reader& r, Grid& g);
void read_surface(const Reader& r, const fs::path& base, SurfaceSpec& s);
void read_load(const Reader& r, const fs::path& base, LoadSpec& l);
void read_solver(const Reader& r, SolverSpec& s);
void read_output(const Reader& r, OutputSpec& o);
void read_wear(const Reader& r, WearSpec& w);
/// [friction]: the law and its parameters (mu is material.mu); checks force amplitudes against
/// the lowest mu the law reaches.
void read_friction(const Reader& r, const LoadSpec& l, double mu, FrictionSpec& f);
/// Combinations of friction law and wear integrator that a wear run cannot honour.
void check_wear_friction(const Reader& r, const WearSpec& w, const FrictionSpec& f);
/// load.tolerance > 0 or an explicit load.substeps > 1 in a wear run: refused, naming the key;
/// a wear run's rows are solved whole (load.substeps = 1).
void resolve_load_substeps(const Reader& r, const WearSpec& w, const SolverSpec& s, LoadSpec& l);

/// The resolved scenario as INI text: every key with its final value, unset ones as comments.
std::string resolved_text(const Scenario& s);

}  // namespace fretbem::scenario_detail
