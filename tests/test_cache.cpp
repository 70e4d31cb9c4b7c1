#include <gtest/gtest.h>
TEST(Placeholdercache, Nothing) { EXPECT_TRUE(true); }
