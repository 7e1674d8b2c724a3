"""ArchVariety's arches (cathbox.arch): every draw loads as a session (the vessel meshes), its
type is what it says (the vertical distance from the top of the arch to the brachiocephalic
trunk's origin, in common-carotid diameters: I < 1, II 1-2, III > 2; Madhwal 2008), a bovine
arch has the left common carotid on the trunk, and every child starts at its parents' end."""
import os
import tempfile
import unittest

import numpy as np

import cathbox
from cathbox import arch

ARCH = ("ascending_aorta", "aortic_arch_1", "aortic_arch_2", "descending_aorta")
BANDS = {"I": (0.0, 1.0), "II": (1.0, 2.0), "III": (2.0, 3.0)}


class ArchTest(unittest.TestCase):
    def test_every_type_and_bovine_loads_and_is_what_it_says(self):
        folder = tempfile.mkdtemp(prefix="cathbox-arch-")
        seen = 0
        for arch_type in arch.ARCH_TYPES:
            for bovine in (False, True):
                for seed in range(5):
                    rng = np.random.default_rng(1000 * seed + 7)
                    hclm, entry, info = arch.generate(rng, arch_type, bovine, tortuosity=float(rng.uniform(0, 1)))
                    vessel = os.path.join(folder, "arch.hclm")
                    with open(vessel, "w", encoding="utf-8") as f:
                        f.write(hclm)
                    segs = {s["name"]: s for s in cathbox.vessel_segments(vessel)}
                    by_id = {s["id"]: s for s in segs.values()}
                    top = max(s["points"][:, 2].max() for n, s in segs.items() if n in ARCH)
                    d = (top - segs["brachiocephalic_trunk"]["points"][0, 2]) / arch.CCA_DIAMETER_MM
                    lo, hi = BANDS[arch_type]
                    with self.subTest(arch_type=arch_type, bovine=bovine, seed=seed):
                        self.assertGreaterEqual(d, lo - 0.05)
                        self.assertLessEqual(d, hi + 0.05)
                        parent = by_id[segs["left_common_carotid"]["parents"][0]]["name"]
                        self.assertEqual(parent, "brachiocephalic_trunk" if bovine else "aortic_arch_1")
                        for s in segs.values():
                            for p in s["parents"]:
                                np.testing.assert_allclose(s["points"][0, :3], by_id[p]["points"][-1, :3], atol=1e-9)
                        case = os.path.join(folder, "arch.case")
                        with open(case, "w", encoding="utf-8") as f:
                            f.write(f"cathbox-case 1\nname arch\nvessel arch.hclm\n{entry}\n"
                                    f"target {segs['left_subclavian_1']['id']} 1.0\n"
                                    "tool guidewire guidewire\n  section 1800 od=0.36 ei=40 gj=31\nend\n")
                        s = cathbox.Session(case)
                        s.set_speeds([[30.0, 0.0]])
                        self.assertEqual(s.step(200), 200)  # the wire enters the descending aorta
                        self.assertGreater(len(s.nodes(0)), 1)
                        seen += 1
        self.assertEqual(seen, 30)

    def test_bad_arguments(self):
        rng = np.random.default_rng(0)
        with self.assertRaises(ValueError):
            arch.generate(rng, "IV")
        with self.assertRaises(ValueError):
            arch.generate(rng, "I", tortuosity=3.0)


if __name__ == "__main__":
    unittest.main()
