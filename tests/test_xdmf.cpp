// result.xmf read back with Debian's Xdmf3 library (the reader ParaView's XDMF plugin is built
// on): time steps, mesh origin and spacing, cell centring and field values are checked against
// the scenario and the time series, not against the writer's own text.
#include <gtest/gtest.h>
#include <unistd.h>

#include <XdmfArray.hpp>
#include <XdmfAttribute.hpp>
#include <XdmfAttributeCenter.hpp>
#include <XdmfDomain.hpp>
#include <XdmfGridCollection.hpp>
#include <XdmfGridCollectionType.hpp>
#include <XdmfReader.hpp>
#include <XdmfRegularGrid.hpp>
#include <XdmfTime.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace fretbem;

namespace {

const fs::path kScenario = fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "mindlin_cycle.ini";
const std::vector<std::string> kSets = {"grid.n=16", "load.cycles=1", "load.steps_per_cycle=16",
                                        "output.fields=pressure,state,slip_x",
                                        "output.fields_every=4"};

fs::path run_small(const std::string& tag, const std::vector<std::string>& sets = kSets) {
  const fs::path dir = fretbem_test::process_temp_dir().vacant(tag);
  std::string cmd = std::string(FRETBEM_BINARY) + " run " + kScenario.string() + " --quiet";
  for (const auto& s : sets) cmd += " --set " + s;
  cmd += " --out " + dir.string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return dir;
}

shared_ptr<XdmfGridCollection> read_collection(const fs::path& xmf) {
  shared_ptr<XdmfReader> reader = XdmfReader::New();
  auto domain = shared_dynamic_cast<XdmfDomain>(reader->read(xmf.string()));
  EXPECT_TRUE(domain);
  EXPECT_EQ(domain->getNumberGridCollections(), 1u);
  return domain->getGridCollection(0);
}

}  // namespace

TEST(Xdmf, ReadBackByXdmf3ShowsEverySavedStepOnTheGrid) {
  const fs::path dir = run_small("steps");
  const Scenario sc = load_scenario(kScenario, kSets);
  const double h = sc.grid.h, L = sc.grid.length_x();
  const auto ts = csv::read_table(dir / "timeseries.csv", {.allow_nan = true});
  const auto& cols = ts.columns;
  const auto col = [&](const std::string& n) {
    return std::size_t(std::find(cols.begin(), cols.end(), n) - cols.begin());
  };

  const auto coll = read_collection(dir / "result.xmf");
  EXPECT_EQ(coll->getType(), XdmfGridCollectionType::Temporal());
  // Saved: every 4th of 17 steps (0, 4, ..., 16) plus the turning points at 4 and 12.
  ASSERT_EQ(coll->getNumberRegularGrids(), 5u);
  for (unsigned k = 0; k < coll->getNumberRegularGrids(); ++k) {
    const auto g = coll->getRegularGrid(k);
    const std::size_t step = 4 * k;
    EXPECT_DOUBLE_EQ(g->getTime()->getValue(), ts.rows[step][col("time")]);
    // Node counts in (z, y, x) order: one node at z = 0, the grid's cells in y and x; origin
    // at the corner of the domain, spacing grid.length / n.
    const auto dims = g->getDimensions(), origin = g->getOrigin(), brick = g->getBrickSize();
    ASSERT_EQ(dims->getSize(), 3u);
    EXPECT_EQ(dims->getValue<unsigned>(0), 1u);
    EXPECT_EQ(dims->getValue<unsigned>(1), 17u);
    EXPECT_EQ(dims->getValue<unsigned>(2), 17u);
    EXPECT_EQ(origin->getValue<double>(0), 0.0);
    for (unsigned a = 0; a < 3; ++a) EXPECT_NEAR(brick->getValue<double>(a), h, 1e-15 * h);
    for (unsigned a = 1; a < 3; ++a) EXPECT_NEAR(origin->getValue<double>(a), -L / 2, 1e-15 * L);
    for (const char* name : {"pressure", "state", "slip_x", "surface_initial"}) {
      const auto a = g->getAttribute(name);
      ASSERT_TRUE(a) << name;
      EXPECT_EQ(a->getCenter(), XdmfAttributeCenter::Cell()) << name;
    }
    // The pressure integrates to the normal force of the time series (step k's row).
    const auto p = g->getAttribute("pressure");
    p->read();
    ASSERT_EQ(p->getSize(), 256u);
    double force = 0;
    for (unsigned c = 0; c < p->getSize(); ++c) force += p->getValue<double>(c) * h * h;
    EXPECT_NEAR(force, ts.rows[step][col("Fz")], 1e-9 * std::abs(ts.rows[step][col("Fz")]));
    // state holds 0/1/2 only; its stick + slip cells make up the contact area of the row.
    const auto st = g->getAttribute("state");
    st->read();
    double contact = 0;
    for (unsigned c = 0; c < st->getSize(); ++c) {
      const int v = st->getValue<int>(c);
      EXPECT_TRUE(v >= 0 && v <= 2) << v;
      contact += (v != 0) * h * h;
    }
    EXPECT_NEAR(contact, ts.rows[step][col("contact_area")], 1e-12 * L * L);
  }
  fs::remove_all(dir);
}

TEST(Xdmf, ResumedRunDescribesTheStepsOfBothParts) {
  const fs::path dir = fretbem_test::process_temp_dir().vacant("resume");
  std::string cmd = std::string(FRETBEM_BINARY) + " run " + kScenario.string() + " --quiet";
  for (const auto& s : kSets) cmd += " --set " + s;
  ASSERT_EQ(std::system((cmd + " --out " + dir.string() + " --stop-after 6 > /dev/null").c_str()),
            0);
  EXPECT_EQ(read_collection(dir / "result.xmf")->getNumberRegularGrids(), 2u);  // steps 0, 4
  ASSERT_EQ(std::system((std::string(FRETBEM_BINARY) + " run --resume " + dir.string() +
                         " --quiet > /dev/null")
                            .c_str()),
            0);
  EXPECT_EQ(read_collection(dir / "result.xmf")->getNumberRegularGrids(), 5u);
  fs::remove_all(dir);
}

// Without output.fields_every a run saves step 0 (the state after the normal loading), the
// turning points and the last step; step 0's pressure carries the scenario's normal force.
TEST(Xdmf, PlainRunSavesStepZeroTurningPointsAndTheLastStep) {
  const std::vector<std::string> sets(kSets.begin(), kSets.end() - 1);  // no fields_every
  const fs::path dir = run_small("plain", sets);
  const Scenario sc = load_scenario(kScenario, sets);
  const double h = sc.grid.h;
  const auto coll = read_collection(dir / "result.xmf");
  // 16 steps per cycle: turning points at 4 and 12 (the force's extremes), the last at 16.
  ASSERT_EQ(coll->getNumberRegularGrids(), 4u);
  const double times[4] = {0.0, 4 / 16.0, 12 / 16.0, 1.0};
  for (unsigned k = 0; k < 4; ++k)
    EXPECT_NEAR(coll->getRegularGrid(k)->getTime()->getValue(), times[k], 1e-12) << k;
  const auto p = coll->getRegularGrid(0)->getAttribute("pressure");
  ASSERT_TRUE(p);
  p->read();
  double force = 0;
  for (unsigned c = 0; c < p->getSize(); ++c) force += p->getValue<double>(c) * h * h;
  EXPECT_NEAR(force, *sc.load.normal_force, 1e-9 * *sc.load.normal_force);
  fs::remove_all(dir);
}
