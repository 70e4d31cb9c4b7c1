#include <gtest/gtest.h>
TEST(Placeholdersurfacing, Nothing) { EXPECT_TRUE(true); }
