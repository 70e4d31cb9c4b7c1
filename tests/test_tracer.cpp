#include <gtest/gtest.h>
TEST(Placeholdertracer, Nothing) { EXPECT_TRUE(true); }
