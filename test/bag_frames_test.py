#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""scripts/bag_frames on tiny bags written here: repeated stamps, empty and inconsistent images, write failures,
unusable bags, output folders and options. Each case checks the files written, the exit status and that the
message names what is wrong, and that no case ends in a Python traceback.

Run by rostest (test/bag_frames.test, `catkin_make run_tests`), or directly: test/bag_frames_test.py --text
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy
import rosbag
import rospy
from sensor_msgs.msg import CameraInfo, Image

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "bag_frames")
TOPIC = "/stereo/left/image_raw"


def image_msg(encoding, width, height, channels, stamp_s, step=None, data=None):
    msg = Image()
    msg.header.stamp = rospy.Time.from_sec(stamp_s)
    msg.encoding, msg.width, msg.height = encoding, width, height
    msg.step = width * channels if step is None else step
    msg.data = bytes(msg.step * height) if data is None else bytes(data)
    return msg


class BagFramesTest(unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="bag_frames_test_")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def path(self, name):
        return os.path.join(self.dir, name)

    def write_bag(self, name, messages):
        """MESSAGES: (topic, msg) in recording order, received 0.1 s apart."""
        path = self.path(name)
        with rosbag.Bag(path, "w") as bag:
            for i, (topic, msg) in enumerate(messages):
                bag.write(topic, msg, rospy.Time(100) + rospy.Duration(0.1 * i))
        return path

    def run_tool(self, *args):
        """(exit status, stdout, stderr); fails the test on a traceback or a hang."""
        p = subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True, timeout=60,
                           check=False)
        self.assertNotIn("Traceback", p.stderr, p.stderr)
        return p.returncode, p.stdout, p.stderr

    def pngs(self, out):
        return sorted(f for f in os.listdir(out) if f.endswith(".png"))

    def test_repeated_stamps_get_unique_names_in_bag_order(self):
        # Stamps left at 0 by a driver, then a frame with a real stamp; pixel value = position in the bag.
        msgs = [(TOPIC, image_msg("mono8", 2, 2, 1, 0, data=[i] * 4)) for i in range(3)]
        msgs.append((TOPIC, image_msg("mono8", 2, 2, 1, 5, data=[3] * 4)))
        bag, out = self.write_bag("same.bag", msgs), self.path("out")
        status, stdout, stderr = self.run_tool(bag, out, "--every", "1")
        self.assertEqual(status, 0, stderr)
        names = self.pngs(out)
        self.assertEqual(names, ["0000000000000000000.png", "0000000000000000000_000001.png",
                                 "0000000000000000000_000002.png", "0000000005000000000.png"])
        self.assertEqual([int(cv2.imread(os.path.join(out, n))[0, 0, 0]) for n in names], [0, 1, 2, 3])
        self.assertIn("wrote 4 images", stdout)
        self.assertIn("2 named <stamp>_<index>.png", stdout)

    def test_every_keeps_one_in_n(self):
        msgs = [(TOPIC, image_msg("mono8", 2, 2, 1, i + 1)) for i in range(7)]
        bag, out = self.write_bag("seven.bag", msgs), self.path("out")
        status, stdout, stderr = self.run_tool(bag, out, "--every=3")
        self.assertEqual(status, 0, stderr)
        self.assertEqual(self.pngs(out), ["0000000001000000000.png", "0000000004000000000.png",
                                          "0000000007000000000.png"])
        self.assertIn("wrote 3 images", stdout)

    def test_empty_image_is_skipped_and_counted(self):
        bgr = image_msg("bgr8", 2, 1, 3, 2, data=[10, 20, 30, 40, 50, 60])
        mono = image_msg("mono8", 2, 1, 1, 3, data=[7, 200])
        rgb = image_msg("rgb8", 1, 1, 3, 4, data=[255, 0, 0])
        msgs = [(TOPIC, image_msg("bgr8", 0, 0, 3, 1)), (TOPIC, bgr), (TOPIC, image_msg("mono8", 0, 0, 1, 1.5)),
                (TOPIC, mono), (TOPIC, rgb)]
        bag, out = self.write_bag("empty.bag", msgs), self.path("out")
        status, stdout, stderr = self.run_tool(bag, out, "--every", "1")
        self.assertEqual(status, 0, stderr)
        self.assertIn(TOPIC + " message 0 (stamp 1.000000000): empty image (0x0 bgr8); skipped", stderr)
        self.assertIn(TOPIC + " message 2 (stamp 1.500000000): empty image (0x0 mono8); skipped", stderr)
        self.assertIn("wrote 3 images", stdout)
        self.assertIn("(2 skipped)", stdout)
        self.assertEqual(self.pngs(out), ["0000000002000000000.png", "0000000003000000000.png",
                                          "0000000004000000000.png"])
        numpy.testing.assert_array_equal(cv2.imread(self.path("out/0000000002000000000.png")),
                                         [[[10, 20, 30], [40, 50, 60]]])
        numpy.testing.assert_array_equal(cv2.imread(self.path("out/0000000003000000000.png")),
                                         [[[7, 7, 7], [200, 200, 200]]])
        numpy.testing.assert_array_equal(cv2.imread(self.path("out/0000000004000000000.png")), [[[0, 0, 255]]])

    def test_inconsistent_sizes_are_named(self):
        msgs = [(TOPIC, image_msg("bgr8", 320, 1, 3, 1, step=480)),
                (TOPIC, image_msg("bgr8", 160, 2, 3, 2, step=480, data=bytes(500))),
                (TOPIC, image_msg("mono16", 2, 2, 2, 3))]
        bag, out = self.write_bag("step.bag", msgs), self.path("out")
        status, stdout, stderr = self.run_tool(bag, out, "--every", "1")
        self.assertEqual(status, 1)  # nothing written
        self.assertIn("message 0 (stamp 1.000000000): step 480 bytes is less than width 320 x 3 channel(s) = 960 bytes",
                      stderr)
        self.assertIn("message 1 (stamp 2.000000000): data has 500 bytes, less than step 480 x height 2 = 960 bytes",
                      stderr)
        self.assertIn("message 2 (stamp 3.000000000): encoding 'mono16' is not read", stderr)
        self.assertIn("wrote 0 images", stdout)
        self.assertIn("no image written", stderr)
        self.assertEqual(self.pngs(out), [])

    def test_failed_write_stops_and_says_how_many_were_written(self):
        msgs = [(TOPIC, image_msg("mono8", 2, 2, 1, i + 1)) for i in range(3)]
        bag, out = self.write_bag("three.bag", msgs), self.path("out")
        os.makedirs(os.path.join(out, "0000000002000000000.png"))  # a folder where the second frame goes
        status, stdout, stderr = self.run_tool(bag, out, "--every", "1")
        self.assertEqual(status, 1)
        self.assertIn(os.path.join(out, "0000000002000000000.png") + ": cannot write message 1 of " + TOPIC, stderr)
        self.assertIn("stopped after writing 1 image(s)", stderr)
        self.assertNotIn("wrote", stdout)
        self.assertEqual(self.pngs(out), ["0000000001000000000.png", "0000000002000000000.png"])
        self.assertTrue(os.path.isdir(os.path.join(out, "0000000002000000000.png")))

    @unittest.skipUnless(os.path.exists("/dev/full"), "needs /dev/full")
    def test_full_disk_is_reported(self):
        msgs = [(TOPIC, image_msg("mono8", 2, 2, 1, i + 1)) for i in range(2)]
        bag, out = self.write_bag("two.bag", msgs), self.path("out")
        os.makedirs(out)
        os.symlink("/dev/full", os.path.join(out, "0000000002000000000.png"))
        status, _, stderr = self.run_tool(bag, out, "--every", "1")
        self.assertEqual(status, 1)
        self.assertIn("0000000002000000000.png: cannot write message 1 of %s (No space left on device); "
                      "stopped after writing 1 image(s)" % TOPIC, stderr)

    def test_unusable_output_folder(self):
        bag = self.write_bag("one.bag", [(TOPIC, image_msg("mono8", 2, 2, 1, 1))])
        a_file = self.path("a_file")
        with open(a_file, "w") as f:
            f.write("x")
        for out, why in [(a_file, "exists and is not a folder"), (os.path.join(a_file, "sub"), "cannot be created"),
                         ("/proc/bag_frames_test/out", "cannot be created")]:
            status, _, stderr = self.run_tool(bag, out)
            self.assertEqual(status, 1, out)
            self.assertIn("output folder %s: %s" % (out, why), stderr)

    def test_unusable_bags(self):
        good = self.write_bag("good.bag", [(TOPIC, image_msg("mono8", 8, 8, 1, i + 1)) for i in range(20)]
                              + [("/stereo/left/camera_info", CameraInfo())])
        empty_bag = self.write_bag("no_messages.bag", [])
        with open(good, "rb") as f:
            data = f.read()
        truncated = self.path("truncated.bag")
        with open(truncated, "wb") as f:
            f.write(data[:len(data) // 2])
        damaged = self.path("damaged.bag")  # index intact, a message record's op code made one rosbag does not know
        at = data.index(b"op=\x02")
        with open(damaged, "wb") as f:
            f.write(data[:at] + b"op=\x7f" + data[at + 4:])
        not_a_bag = self.path("notes.bag")
        with open(not_a_bag, "w") as f:
            f.write("not a bag\n")
        zero = self.path("zero.bag")
        open(zero, "w").close()
        out = self.path("out")
        cases = [([empty_bag], 1, "the bag holds no messages"),
                 ([truncated], 1, "has no index (recording cut short?); try 'rosbag reindex"),
                 ([damaged], 1, "cannot be read"),
                 ([not_a_bag], 1, "cannot be read as a bag"),
                 ([zero], 1, "is empty (0 bytes), not a bag"),
                 ([self.path("missing.bag")], 1, "no such file"),
                 ([self.dir], 1, "is a directory, not a bag"),
                 ([good, "--topic", "/nope"], 1, "no topic /nope (image topics: %s)" % TOPIC),
                 ([good, "--topic", "/stereo/left/camera_info"], 1,
                  "topic /stereo/left/camera_info holds sensor_msgs/CameraInfo, not sensor_msgs/Image")]
        for args, expected_status, message in cases:
            status, _, stderr = self.run_tool(args[0], out, *args[1:])
            self.assertEqual(status, expected_status, (args, stderr))
            self.assertIn(message, stderr, args)
            self.assertIn(os.path.basename(args[0]), stderr, args)

    def test_bad_options(self):
        bag = self.write_bag("one.bag", [(TOPIC, image_msg("mono8", 2, 2, 1, 1))])
        out = self.path("out")
        for args, message in [([bag, out, "--every", "0"], "--every must be a whole number of at least 1"),
                              ([bag, out, "--every", "-3"], "got '-3'"),
                              ([bag, out, "--every", "x"], "got 'x'"),
                              ([bag, out, "--every"], "--every needs a value"),
                              ([bag, out, "--topic"], "--topic needs a value"),
                              ([bag, out, "--frobnicate"], "unknown option '--frobnicate'"),
                              ([bag, out, "--every", "2", "--every=5"], "--every is given twice"),
                              ([bag, out, "--topic", "/a", "--topic", "/b"], "--topic is given twice"),
                              ([bag], "needs BAG and DIR, got 1 argument(s)")]:
            status, _, stderr = self.run_tool(*args)
            self.assertEqual(status, 2, args)
            self.assertIn(message, stderr, args)
        self.assertFalse(os.path.exists(out))
        status, stdout, _ = self.run_tool("--help")
        self.assertEqual(status, 0)
        self.assertIn("usage:", stdout)


if __name__ == "__main__":
    import rosunit
    rosunit.unitrun("underwater_stereo", "bag_frames", BagFramesTest)
