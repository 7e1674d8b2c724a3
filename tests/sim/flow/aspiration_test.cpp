// Aspiration thrombectomy: vacuum force against pressure x area, and the clot's fate.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "flow/aspiration.hpp"

namespace cathbox::flow {
namespace {

struct Catheter {
  const char* name;
  double inner_diameter_in;
};
// Inner diameters as labelled (inches).
constexpr Catheter kCatheters[] = {{"3MAX", 0.035}, {"ACE 60", 0.060}, {"ACE 64", 0.064}, {"ACE 68", 0.068}, {"React 71", 0.071}};

// Froehler, JNIS 2017: pump -25.6 inHg, 60 mL syringe -27.0 inHg; force = pressure x area.
TEST(Aspiration, ForceIsPressureTimesLumenArea) {
  for (const Catheter& c : kCatheters) {
    const double d_m = c.inner_diameter_in * 0.0254;
    const double area_m2 = 3.14159265358979 * d_m * d_m / 4.0;
    const double pump_Pa = 25.6 * 101325.0 / 29.9213;  // 1 atm = 29.9213 inHg
    const double syringe_Pa = 27.0 * 101325.0 / 29.9213;
    const double d_mm = c.inner_diameter_in * 25.4;
    EXPECT_NEAR(aspiration_force_N(VacuumSource::kPump, d_mm), pump_Pa * area_m2, 1e-5 * pump_Pa * area_m2) << c.name;
    EXPECT_NEAR(aspiration_force_N(VacuumSource::kSyringe60, d_mm), syringe_Pa * area_m2, 1e-5 * syringe_Pa * area_m2) << c.name;
    std::printf("%-8s ID %.3f in: pump %.3f N, syringe %.3f N\n", c.name, c.inner_diameter_in,
                aspiration_force_N(VacuumSource::kPump, d_mm), aspiration_force_N(VacuumSource::kSyringe60, d_mm));
  }
  EXPECT_LT(vacuum_Pa(VacuumSource::kPump), 0.0);
  EXPECT_LT(vacuum_Pa(VacuumSource::kSyringe60), vacuum_Pa(VacuumSource::kPump));
}

// The pressure difference across a 13 mm M1 clot in the neuro case, flowing (Occlusion tests:
// ~12 kPa), and a head fully removed by flow arrest.
constexpr double kHeadFlowing_Pa = 12000.0;
constexpr double kHeadArrested_Pa = 0.0;

int rank(AspirationOutcome o) { return o == AspirationOutcome::kIngested ? 2 : (o == AspirationOutcome::kCorked ? 1 : 0); }

// The clot's fate is monotone in what helps: a wider catheter, the syringe's deeper vacuum,
// flow arrest, a softer (red-cell-rich) clot never give a worse outcome.
TEST(Aspiration, OutcomeIsMonotoneInCatheterVacuumFlowArrestAndComposition) {
  const ClotComposition compositions[] = {{80.0, 15.0}, {60.0, 30.0}, {45.0, 45.0}, {30.0, 60.0}, {10.0, 80.0}};
  for (double clot_d : {2.5, 3.1, 3.6}) {
    for (const ClotComposition& comp : compositions) {
      for (double head : {kHeadFlowing_Pa, kHeadArrested_Pa}) {
        int last = -1;
        for (const Catheter& c : kCatheters) {
          const AspirationClot clot{clot_d, 13.0, comp};
          const AspirationResult pump = aspirate(VacuumSource::kPump, c.inner_diameter_in * 25.4, clot, head);
          const AspirationResult syringe = aspirate(VacuumSource::kSyringe60, c.inner_diameter_in * 25.4, clot, head);
          const AspirationResult open = aspirate(VacuumSource::kPump, c.inner_diameter_in * 25.4, clot, kHeadFlowing_Pa);
          EXPECT_GE(rank(pump.outcome), last);
          EXPECT_GE(rank(syringe.outcome), rank(pump.outcome));
          EXPECT_GE(rank(pump.outcome), rank(open.outcome));
          last = rank(pump.outcome);
        }
      }
    }
  }
  // A softer clot is ingested where a stiffer one is not.
  int last = 3;
  for (const ClotComposition& comp : compositions) {
    const int r = rank(aspirate(VacuumSource::kPump, 0.060 * 25.4, {3.1, 13.0, comp}, kHeadArrested_Pa).outcome);
    EXPECT_LE(r, last);
    last = r;
  }
}

// The M1 case (3.1 mm, 13 mm clot): a large-bore catheter on the pump ingests a red-cell-rich
// clot, a fibrin-rich one corks the tip (retrieved by pulling catheter and clot together), and a
// 3MAX on it against the flowing pressure head loses it; without the head (complete flow
// arrest) that corked withdrawal succeeds. A clot narrower than the tip is always ingested.
TEST(Aspiration, M1ClotsAreIngestedCorkedOrLost) {
  const AspirationClot red{3.1, 13.0, {75.0, 20.0}};
  const AspirationClot fibrin{3.1, 13.0, {15.0, 75.0}};
  const AspirationResult a = aspirate(VacuumSource::kPump, 0.071 * 25.4, red, kHeadFlowing_Pa);
  const AspirationResult b = aspirate(VacuumSource::kPump, 0.068 * 25.4, fibrin, kHeadFlowing_Pa);
  const AspirationResult c = aspirate(VacuumSource::kPump, 0.035 * 25.4, fibrin, kHeadFlowing_Pa);
  const AspirationResult d = aspirate(VacuumSource::kPump, 0.035 * 25.4, fibrin, kHeadArrested_Pa);
  std::printf("red-cell-rich, React 71: pull %.3f N, ingest needs %.3f N, hold %.3f N\n", a.force_N, a.ingest_force_N, a.hold_force_N);
  std::printf("fibrin-rich, ACE 68: pull %.3f N, ingest needs %.3f N, hold %.3f N\n", b.force_N, b.ingest_force_N, b.hold_force_N);
  std::printf("fibrin-rich, 3MAX: pull %.3f N, hold %.3f N open, %.3f N arrested\n", c.force_N, c.hold_force_N, d.hold_force_N);
  EXPECT_EQ(a.outcome, AspirationOutcome::kIngested);
  EXPECT_EQ(b.outcome, AspirationOutcome::kCorked);
  EXPECT_EQ(c.outcome, AspirationOutcome::kLost);
  EXPECT_EQ(d.outcome, AspirationOutcome::kCorked);
  EXPECT_EQ(aspirate(VacuumSource::kPump, 0.035 * 25.4, {0.8, 5.0, {10.0, 85.0}}, kHeadFlowing_Pa).outcome, AspirationOutcome::kIngested);
}

}  // namespace
}  // namespace cathbox::flow
