"""The image test's comparison (/usr/bin/python3): the rule of the project's other image tests
(Testing/Python/TerroirImages.py: every pixel within 8 levels of a pixel within one pixel of it,
both ways, at most 16 pixels otherwise).
    CompareImage.py TEST.png BASELINE.png"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..',
                                'Testing', 'Python'))
import TerroirImages  # noqa: E402

test, baseline = sys.argv[1:3]
bad, worst = TerroirImages.compare_images(TerroirImages.read_rgb(test),
                                          TerroirImages.read_rgb(baseline))
print('%s: %d pixels match nothing in %s (largest difference %d)' % (test, bad, baseline, worst))
sys.exit(0 if bad <= TerroirImages.DIFFERING_PIXELS else 1)
