// Label tables in the formats the atlases and segmentation tools write, and --labels lists.

#include <gtest/gtest.h>

#include <fstream>

#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

std::filesystem::path write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

TEST(LabelTableTest, ReadsTheMricronTextWithItsCodeColumn) {
    ScratchDir dir;
    const LabelTable table = read_label_table(write_text(dir / "aal.nii.txt", "1 Precentral_L 2001\n2 Precentral_R 2002\n"));
    ASSERT_EQ(table.size(), 2u);
    EXPECT_EQ(table.at(2).name, "Precentral_R");
    EXPECT_FALSE(table.at(1).color);
}

TEST(LabelTableTest, ReadsFreeSurferColoursAndSkipsComments) {
    ScratchDir dir;
    const LabelTable table = read_label_table(write_text(dir / "lut.txt", "# FreeSurfer\n\n0 Unknown 0 0 0 0\n17 Left-Hippocampus 220 216 20 0\n"));
    ASSERT_EQ(table.size(), 2u);
    EXPECT_EQ(table.at(17).name, "Left-Hippocampus");
    EXPECT_EQ(*table.at(17).color, (std::array<std::uint8_t, 3>{220, 216, 20}));
}

TEST(LabelTableTest, ReadsItkSnapQuotedNames) {
    ScratchDir dir;
    const LabelTable table = read_label_table(write_text(dir / "snap.label", "    5   255  128    0        1  1  1    \"Left kidney\"\n"));
    ASSERT_EQ(table.size(), 1u);
    EXPECT_EQ(table.at(5).name, "Left kidney");
    EXPECT_EQ(*table.at(5).color, (std::array<std::uint8_t, 3>{255, 128, 0}));
}

TEST(LabelTableTest, ErrorsNameTheFileTheLineAndTheValue) {
    ScratchDir dir;
    const auto twice = write_text(dir / "twice.txt", "1 a\n1 b\n");
    try {
        read_label_table(twice);
        FAIL() << "no error";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("twice.txt: line 2"), std::string::npos) << e.what();
    }
    EXPECT_THROW(read_label_table(write_text(dir / "neg.txt", "-3 a\n")), FormatError);
    EXPECT_THROW(read_label_table(write_text(dir / "big.txt", "70000 a\n")), FormatError);
    EXPECT_THROW(read_label_table(write_text(dir / "nameless.txt", "4\n")), FormatError);
    EXPECT_THROW(read_label_table(dir / "missing.txt"), FormatError);
}

TEST(LabelTableTest, FindsTheTableBesideTheScan) {
    ScratchDir dir;
    write_text(dir / "aal.nii.txt", "1 a\n");
    EXPECT_EQ(find_label_table(dir / "aal.nii.gz"), dir / "aal.nii.txt");
    write_text(dir / "seg.lut", "1 a\n");
    EXPECT_EQ(find_label_table(dir / "seg.nii"), dir / "seg.lut");
    EXPECT_FALSE(find_label_table(dir / "other.nii.gz"));
}

TEST(LabelTableTest, ParsesLabelLists) {
    EXPECT_TRUE(parse_label_list("all").empty());
    EXPECT_EQ(parse_label_list("5,3,10-12,3"), (std::vector<std::uint32_t>{3, 5, 10, 11, 12}));
    for (const char* bad : {"", "0", "x", "3-1", "70000", "1,,a", "-2"}) EXPECT_THROW(parse_label_list(bad), UsageError) << bad;
}

}  // namespace
}  // namespace vdbmesh
