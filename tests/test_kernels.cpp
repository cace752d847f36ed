#include <gtest/gtest.h>
#include "sphflume/core/kernels.hpp"
TEST(Kernels, Placeholder) { EXPECT_EQ(sph::kernel_support_factor(sph::KernelType::WendlandC2), 2.0); }
