#include "pf2/core/command_line.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(CommandLine, OptionsFlagsAndPositionals) {
  const char* argv[] = {"app", "gt.txt", "--delta", "0.5", "--json", "est.txt", "--offset", "-2"};
  CommandLine cli(8, argv);
  EXPECT_FALSE(cli.helpRequested());
  EXPECT_TRUE(cli.flag("--json"));
  EXPECT_FALSE(cli.flag("--rpe"));
  EXPECT_DOUBLE_EQ(cli.number("--delta", 1.0), 0.5);
  EXPECT_EQ(cli.integer("--offset", 0), -2);
  EXPECT_EQ(cli.integer("--frames", 7), 7);
  EXPECT_EQ(cli.positionals(), (std::vector<std::string>{"gt.txt", "est.txt"}));
}

TEST(CommandLine, ErrorsNameTheOption) {
  const char* argv[] = {"app", "--delta", "abc", "--bogus", "--plot"};
  CommandLine cli(5, argv);
  try {
    cli.number("--delta", 1.0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--delta"), std::string::npos);
  }
  EXPECT_THROW(cli.value("--plot"), Error);  // value missing
  EXPECT_THROW(cli.positionals(), Error);    // --bogus unknown
}

TEST(CommandLine, Help) {
  const char* argv[] = {"app", "x", "-h"};
  EXPECT_TRUE(CommandLine(3, argv).helpRequested());
}

}  // namespace
}  // namespace pf2
