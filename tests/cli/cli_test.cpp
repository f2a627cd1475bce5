#include <gtest/gtest.h>

#include "cli.h"

namespace vdbmesh::cli {

TEST(CliTest, HelpSucceeds) { EXPECT_EQ(run({"--help"}), kSuccess); }

TEST(CliTest, UnknownSubcommandIsUsageError) { EXPECT_EQ(run({"frobnicate"}), kUsageError); }

TEST(CliTest, NoSubcommandIsUsageError) { EXPECT_EQ(run({}), kUsageError); }

TEST(CliTest, SubcommandHelpSucceeds) {
    for (const char* name : {"info", "convert", "phantom"}) EXPECT_EQ(run({name, "--help"}), kSuccess) << name;
}

}  // namespace vdbmesh::cli
