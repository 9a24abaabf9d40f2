// Helpers of the Spine reader tests.
#ifndef KOMA_TESTS_FORMATS_SPINE_TEST_UTIL_H_
#define KOMA_TESTS_FORMATS_SPINE_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <string>

#include "core/curves.h"
#include "formats/spine.h"

namespace koma::formats {

// The curve `id` of a read animation; a test failure (and an empty curve) when there is none.
inline const Curve& CurveNamed(const SpineAnimation& animation, const std::string& id) {
  for (const Curve& curve : animation.curves.curves) {
    if (curve.id == id) return curve;
  }
  ADD_FAILURE() << "no curve " << id;
  static const Curve kNone;
  return kNone;
}

}  // namespace koma::formats

#endif  // KOMA_TESTS_FORMATS_SPINE_TEST_UTIL_H_
