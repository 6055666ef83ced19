// The verdict rule every caption states, the CSV writer, and the registry's contract: every figure
// the issue asks for is registered once, with a source and a claim.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "harness/figures/figure.h"

namespace aoeval::figures {
namespace {

TEST(Verdict, AllChecksPassIsReproduced) {
  EXPECT_EQ(verdict_of({{"a", true, ""}, {"b", true, ""}}), Verdict::reproduced);
}

TEST(Verdict, SomeChecksPassIsPartlyReproduced) {
  EXPECT_EQ(verdict_of({{"a", true, ""}, {"b", false, ""}}), Verdict::partly_reproduced);
  EXPECT_EQ(verdict_of({{"a", false, ""}, {"b", false, ""}, {"c", true, ""}}),
            Verdict::partly_reproduced);
}

TEST(Verdict, NoPassingCheckIsNotReproduced) {
  EXPECT_EQ(verdict_of({{"a", false, ""}}), Verdict::not_reproduced);
  EXPECT_EQ(verdict_of({}), Verdict::not_reproduced);  // nothing measured: no claim reproduced
}

TEST(Verdict, NamesAreTheCaptionWords) {
  EXPECT_STREQ(verdict_name(Verdict::reproduced), "reproduced");
  EXPECT_STREQ(verdict_name(Verdict::partly_reproduced), "partly reproduced");
  EXPECT_STREQ(verdict_name(Verdict::not_reproduced), "not reproduced");
}

TEST(Caption, StatesEveryCheckTheVerdictAndItsRule) {
  Figure f{"x-fig1", "X et al., Fig. 1", "the claim", nullptr};
  FigureResult r;
  r.measured = "what we ran";
  r.checks = {{"error < 0.1", true, "0.05"}, {"faster", false, "1.2x"}};
  r.notes = {"a caveat"};
  const std::string c = caption_text(f, r);
  EXPECT_NE(c.find("Claim: the claim"), std::string::npos);
  EXPECT_NE(c.find("Measured: what we ran"), std::string::npos);
  EXPECT_NE(c.find("[pass] error < 0.1: 0.05"), std::string::npos);
  EXPECT_NE(c.find("[fail] faster: 1.2x"), std::string::npos);
  EXPECT_NE(c.find("Verdict: partly reproduced"), std::string::npos);
  EXPECT_NE(c.find(kVerdictRule), std::string::npos);
  EXPECT_NE(c.find("- a caveat"), std::string::npos);
}

TEST(Table, CsvQuotesWhereNeededAndRejectsRaggedRows) {
  Table t;
  t.columns = {"name", "value"};
  t.add({"plain", "1.5"});
  t.add({"has,comma", "say \"hi\""});
  EXPECT_EQ(to_csv(t), "name,value\nplain,1.5\n\"has,comma\",\"say \"\"hi\"\"\"\n");
  EXPECT_THROW(t.add({"only one"}), std::invalid_argument);
}

TEST(Table, NumbersKeepSignificantDigitsAndSpellNonFinite) {
  EXPECT_EQ(fmt(0.123456789), "0.1235");
  EXPECT_EQ(fmt(1234567.0, 3), "1.23e+06");
  EXPECT_EQ(fmt(std::nan("")), "nan");
  EXPECT_EQ(fmt(-HUGE_VAL), "-inf");
}

TEST(Registry, HoldsEveryFigureTheIssueNamesOnce) {
  const std::set<std::string> wanted = {"hegeman-fig2",       "hegeman-fig8",   "hegeman-fig12",
                                        "hegeman-throughput", "dimitrov-fig6",  "dimitrov-fig7",
                                        "dimitrov-fig11",     "dimitrov-fig12", "dimitrov-table1",
                                        "mendez-fig6",        "mendez-fig7",    "gpugems-fig17-3"};
  std::set<std::string> seen;
  for (const auto& f : figure_registry()) {
    EXPECT_TRUE(seen.insert(f.name).second) << f.name << " registered twice";
    EXPECT_FALSE(f.source.empty()) << f.name;
    EXPECT_FALSE(f.claim.empty()) << f.name;
    EXPECT_TRUE(f.make) << f.name;
  }
  for (const auto& name : wanted) {
    EXPECT_TRUE(seen.count(name)) << name << " missing";
    EXPECT_NE(find_figure(name), nullptr);
  }
  EXPECT_EQ(find_figure("no-such-figure"), nullptr);
}

}  // namespace
}  // namespace aoeval::figures
