"""cathbox.Session: the program's hand, zero-copy state, clone, bad arguments."""
import math
import os
import unittest

import numpy as np

import cathbox

Y = cathbox.case_path("y_bifurcation")


class SessionTest(unittest.TestCase):
    def test_speeds_integrate_into_whole_micrometres(self):
        s = cathbox.Session(Y)
        s.set_speeds(np.array([[10.0, 0.5]]))
        self.assertEqual(s.step(100), 100)  # 100 ms at 10 mm/s and 0.5 rad/s
        self.assertAlmostEqual(s.insertion_mm(0), 1.0, places=9)
        self.assertAlmostEqual(s.rotation_rad(0), 0.05, places=9)
        s.set_speeds(np.array([[-50.0, 0.0]]))
        s.step(100)  # pulled back past the entry: held at 0, no dead zone
        self.assertEqual(s.insertion_mm(0), 0.0)
        s.set_speeds(np.array([[0.15, 0.0]]))  # 0.15 um per tick: whole um, fractions kept
        s.step(20)
        self.assertAlmostEqual(s.insertion_mm(0), 0.003, places=9)

    def test_nodes_are_read_only_views_kept_alive_by_the_session(self):
        s = cathbox.Session(Y)
        s.set_speeds([[20.0, 0.0]])
        s.step(300)
        a = s.nodes(0)
        b = s.nodes(0)
        self.assertEqual(a.shape[1], 3)
        self.assertGreater(a.shape[0], 2)
        self.assertTrue(np.shares_memory(a, b))  # no copy: both view the session's state
        self.assertFalse(a.flags.writeable)
        self.assertIs(a.base, s)
        with self.assertRaises(ValueError):
            a[0, 0] = 1.0
        np.testing.assert_array_equal(a[-1], s.tip(0)[0])

    def test_node_buffer_is_the_simulators_memory_live_and_kept_alive(self):
        import gc
        import weakref
        s = cathbox.Session(cathbox.case_path("neuro"))  # catheter, guidewire inside it
        views = [s.node_buffer(t) for t in range(s.tool_count)]
        address = [v.__array_interface__["data"][0] for v in views]
        self.assertFalse(any(v.flags.owndata or v.flags.writeable for v in views))
        self.assertTrue(all(v.base is s for v in views))
        self.assertTrue(np.shares_memory(views[1], s.node_buffer(1)))
        before = [v.copy() for v in views]
        s.set_speeds([[20.0, 0.0], [20.0, 1.0]])
        s.step(400)
        for t, v in enumerate(views):  # the same memory, now holding the state after the step
            self.assertEqual(s.node_buffer(t).__array_interface__["data"][0], address[t])
            self.assertGreater(np.abs(v - before[t]).max(), 1.0)
            np.testing.assert_array_equal(v[-1], s.tip(t)[0])  # the tip is the rod's last node
        np.testing.assert_array_equal(views[0][-len(s.nodes(0)):], s.nodes(0))  # the outer tool: its nodes
        # Lifetime: the views keep the session (and the simulator's buffers) alive; the last one
        # to go frees it. Under the ASan step a freed buffer read here would be reported.
        tip = s.tip(1)[0]
        alive = weakref.ref(s)
        s.close()
        del s
        gc.collect()
        self.assertIsNotNone(alive())
        np.testing.assert_array_equal(views[1][-1], tip)
        base = views[0].base
        del views, base, v
        gc.collect()
        self.assertIsNone(alive())
        with self.assertRaises(IndexError):
            cathbox.Session(Y).node_buffer(1)

    def test_route_remaining_is_the_path_left_past_the_tips_closest_route_point(self):
        s = cathbox.Session(Y)
        route = s.route
        seg = np.linalg.norm(np.diff(route, axis=0), axis=1)
        arc = np.concatenate([[0.0], np.cumsum(seg)])
        self.assertAlmostEqual(arc[-1], s.route_length_mm, delta=1e-3)
        for speed in (0.0, 40.0, 40.0, 40.0):
            s.set_speeds([[speed, 2.0]])
            s.step(250)
            tip = s.tip(0)[0]
            a, ab = route[:-1], np.diff(route, axis=0)  # every segment's closest point, by brute force
            t = np.clip(((tip - a) * ab).sum(1) / (ab * ab).sum(1), 0.0, 1.0)
            d = np.linalg.norm(tip - (a + t[:, None] * ab), axis=1)
            i = int(np.argmin(d))
            expected = arc[-1] - (arc[i] + t[i] * seg[i]) + d[i]
            self.assertAlmostEqual(s.route_remaining_mm(0), expected, delta=1e-4)
        self.assertLess(s.route_remaining_mm(0), s.route_length_mm - 20.0)  # 30 mm pushed in: closer

    def test_clone_replays_the_inputs_to_the_same_state(self):
        s = cathbox.Session(Y)
        for v in (15.0, 5.0, 25.0):
            s.set_speeds([[v, 1.0]])
            s.step(150)
        c = s.clone()
        self.assertEqual(c.state_hash(), s.state_hash())
        self.assertEqual(c.ticks, s.ticks)
        for x in (s, c):  # and they go on the same way, independently
            x.set_speeds([[10.0, -2.0]])
            x.step(200)
        self.assertEqual(c.state_hash(), s.state_hash())
        s.step(10)
        self.assertNotEqual(c.state_hash(), s.state_hash())

    def test_points_from_tip_are_the_nodes_resampled_by_arc_length(self):
        # Against numpy: arc length from the tip, linear between nodes, the entry past the end.
        s = cathbox.Session(cathbox.case_path("neuro"))
        rng = np.random.default_rng(1)
        for _ in range(20):
            s.set_speeds(rng.uniform([-10.0, -3.0], [40.0, 3.0], size=(2, 2)))
            s.step(100)
            for t in range(2):
                rev = np.array(s.nodes(t))[::-1]
                arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(rev, axis=0), axis=1))])
                for count, spacing in ((3, 2.0), (16, 5.0), (60, 3.0), (4, 0.0)):
                    want = np.minimum(np.arange(count) * spacing, arc[-1])
                    expected = np.stack([np.interp(want, arc, rev[:, j]) for j in range(3)], axis=1)
                    np.testing.assert_allclose(s.points_from_tip(t, count, spacing), expected, rtol=0, atol=1e-9)
        with self.assertRaisesRegex(ValueError, "^points_from_tip: count -1 outside"):
            s.points_from_tip(0, -1, 1.0)
        with self.assertRaisesRegex(ValueError, "^points_from_tip: spacing_mm nan"):
            s.points_from_tip(0, 3, float("nan"))
        with self.assertRaisesRegex(IndexError, "^tool 2 out of range"):
            s.points_from_tip(2, 3, 1.0)

    def test_state_observation_is_the_parts_clipped_to_float32_bit_for_bit(self):
        # The envs' state observation in one C++ pass equals the numpy composition it replaced
        # (points_from_tip, tip direction, insertion, rotation per tool; target; last action;
        # numpy.clip to +-1e4 then float32), bit for bit: the envs' observations did not change.
        s = cathbox.Session(cathbox.case_path("neuro"))
        rng = np.random.default_rng(2)
        target = np.array([12.5, -3.25, 2.0e4])  # beyond the clip, to check it
        for _ in range(12):
            action = rng.uniform([-20.0, -3.0], [40.0, 3.0], size=(2, 2))
            action[0, 1] = float("nan") if _ == 5 else action[0, 1]  # NaN passes through as numpy's clip
            s.set_speeds(np.nan_to_num(action))
            s.step(60)
            parts = []
            for t in range(2):
                parts += [s.points_from_tip(t, 16, 5.0).ravel(), s.tip(t)[1], [s.insertion_mm(t), s.rotation_rad(t)]]
            parts += [target, action.ravel()]
            expected = np.clip(np.concatenate(parts), -1e4, 1e4).astype(np.float32)
            got = s.state_observation(16, 5.0, target, action)
            self.assertEqual(got.dtype, np.float32)
            self.assertEqual(got.tobytes(), expected.tobytes())
        with self.assertRaisesRegex(ValueError, "^state_observation: last_action has 2 values, expected 4"):
            s.state_observation(16, 5.0, target, [0.0, 0.0])
        with self.assertRaisesRegex(ValueError, "^state_observation: target has 2 values"):
            s.state_observation(16, 5.0, [1.0, 2.0], action)
        with self.assertRaisesRegex(ValueError, "^state_observation: count -1 outside"):
            s.state_observation(-1, 5.0, target, action)

    def test_a_wire_inside_its_catheter_is_not_counted_unconverged(self):
        # neuro: the catheter, its guidewire inside. The catheter goes in; the wire, not yet out
        # of it, is not solved, so it does not make every tick unconverged (it did: share 1.0).
        s = cathbox.Session(cathbox.case_path("neuro"))
        s.set_speeds([[15.0, 0.0], [15.0, 0.0]])
        s.step(300)
        self.assertLess(s.metrics()["unconverged_share"], 0.05)

    def test_step_releases_the_gil(self):
        # While a thread is inside step(), this thread runs Python: with the GIL held for the
        # whole step it could not run a single iteration until step() returned.
        import threading
        s = cathbox.Session(Y)
        s.set_speeds([[20.0, 1.0]])
        started = threading.Event()

        def work():
            started.set()
            s.step(3000)

        t = threading.Thread(target=work)
        t.start()
        started.wait()
        spins = 0
        while t.is_alive():
            spins += 1
        t.join()
        self.assertEqual(s.ticks, 3000)
        self.assertGreater(spins, 1000)

    def test_bad_arguments_raise_one_clear_line(self):
        with self.assertRaises(ValueError) as e:
            cathbox.Session("/nonexistent/nothing.case")
        self.assertIn("nothing.case", str(e.exception))
        self.assertNotIn("\n", str(e.exception))
        s = cathbox.Session(Y)
        cases = [
            (np.zeros((2, 2)), "shape (2, 2), expected (1, 2)"),
            (np.zeros(3), "shape (3,), expected (1, 2)"),
            (np.array([[math.nan, 0.0]]), "not finite"),
            (np.array([[0.0, math.inf]]), "not finite"),
            ("fast", "action"),
        ]
        for bad, text in cases:
            with self.assertRaises(ValueError) as e:
                s.set_speeds(bad)
            self.assertIn(text, str(e.exception))
            self.assertNotIn("\n", str(e.exception))
        with self.assertRaises(IndexError) as e:
            s.nodes(3)
        self.assertIn("tool 3 out of range", str(e.exception))
        with self.assertRaises(ValueError):
            s.step(-1)
        with self.assertRaises(ValueError):
            s.image(4, 4)
        with self.assertRaises(ValueError) as e:
            s.set_c_arm(lao_deg=500.0)
        self.assertIn("C-arm", str(e.exception))
        self.assertEqual(s.step(5), 5)  # and the session still runs

    def test_image_shows_the_wire_where_it_projects(self):
        s = cathbox.Session(Y)
        s.set_c_arm(0.0, 0.0, 150.0)
        blank = s.image(96, 96)
        s.set_speeds([[30.0, 0.0]])
        s.step(1000)
        img = s.image(96, 96)
        self.assertEqual(img.dtype, np.uint8)
        self.assertEqual(img.shape, (96, 96))
        self.assertEqual(int(blank.min()), int(blank.max()))  # nothing inserted: a flat field
        dark = img < blank.max() - 20
        self.assertGreater(int(dark.sum()), 10)
        # The tip's projection is on a dark pixel (mm on the detector -> pixels: fov 150 mm).
        tip_mm = s.project(s.tip(0)[0][None, :])[0]
        px = 150.0 / 96
        x, y = int(48 + tip_mm[0] / px), int(48 - tip_mm[1] / px)
        self.assertTrue(dark[max(0, y - 2):y + 3, max(0, x - 2):x + 3].any())

    def test_six_tools_take_six_speeds(self):
        # Balloon-assisted coiling's six tools (tests/host/session/data/balloon_remodelling.case):
        # speeds are (6, 2); every tool, the coil (index 5) included, moves by its own.
        here = os.path.dirname(os.path.abspath(__file__))
        s = cathbox.Session(os.path.join(here, "..", "session", "data", "balloon_remodelling.case"))
        self.assertEqual(s.tool_count, 6)
        with self.assertRaises(ValueError) as e:
            s.set_speeds(np.zeros((4, 2)))
        self.assertIn("expected (6, 2)", str(e.exception))
        s.set_speeds(np.array([[10.0, 0.0], [9.0, 0.0], [8.0, 0.0], [7.0, 0.0], [6.0, 0.0], [5.0, 0.5]]))
        self.assertEqual(s.step(100), 100)
        for t, mm in enumerate([1.0, 0.9, 0.8, 0.7, 0.6, 0.5]):
            self.assertAlmostEqual(s.insertion_mm(t), mm, places=9)
        self.assertAlmostEqual(s.rotation_rad(5), 0.05, places=9)


if __name__ == "__main__":
    unittest.main()
