// index.csv, the source of truth for the labels of an objects folder.
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/dataset/objects_index.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {

using testing_support::TemporaryFolderTest;
using ObjectsIndexTest = TemporaryFolderTest;

TEST_F(ObjectsIndexTest, RowsRoundTripWithLabelsThatNeedQuoting) {
  ObjectIndexRow plain{"Sedan-1-1.pcd", "Sedan", "7", "1", 120, 14.4156, 4.8178, 1.7833, 1.423,
                       -0.001502};
  ObjectIndexRow odd{"x.pcd", "Tram, \"old\"\nline", "8", "2", 11, 1.0, 2.0, 3.0, 4.0, 0.5};
  write("index.csv", std::string(objectIndexHeader()) + objectIndexLine(plain) +
                         objectIndexLine(odd));
  const std::vector<ObjectIndexRow> rows = readObjectIndex(root_);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].label, "Sedan");
  EXPECT_EQ(rows[0].points, 120u);
  EXPECT_DOUBLE_EQ(rows[0].height, 1.423);
  EXPECT_EQ(rows[1].label, "Tram, \"old\"\nline");
  EXPECT_DOUBLE_EQ(rows[1].height, 4.0);
}

TEST_F(ObjectsIndexTest, NoIndexIsNoRowsAndABrokenLineIsNamed) {
  EXPECT_TRUE(readObjectIndex(root_).empty());
  write("index.csv", std::string(objectIndexHeader()) + "a.pcd,Sedan,1,2,ten\n");
  try {
    readObjectIndex(root_);
    ADD_FAILURE() << "read a broken line";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("index.csv: line 2"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace granular
