#!/usr/bin/env python3
"""Reads a ROS 1 bag with python3-rosbag (ROS's own reader, not corridorsim's) and writes every
message as JSON, for tests/harness/record/bag_writer_test.cpp to compare with what it wrote.

usage: bag_dump.py BAG OUT_JSON

OUT_JSON is a list, in the bag's order, of
  {"topic", "datatype", "md5sum", "genpy_md5sum", "time_ns", "message"}
where genpy_md5sum is the MD5 that genpy computes from the connection's message_definition
(it must equal md5sum), and message lists the fields in the ROS 1 definition's order (a
sub-message as a list, time and duration as integer nanoseconds, uint8[] as a list of numbers).
"""
import json
import sys

import genpy
import rosbag


def plain(value, slot_type):
    if isinstance(value, genpy.Message):
        return [plain(getattr(value, name), t)
                for name, t in zip(value.__slots__, value._slot_types)]
    if isinstance(value, (genpy.Time, genpy.Duration)):
        return value.secs * 1000000000 + value.nsecs
    element_type = slot_type.split("[")[0]
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, (list, tuple)):
        return [plain(v, element_type) for v in value]
    if slot_type == "bool":
        return bool(value)
    return value


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: bag_dump.py BAG OUT_JSON")
    out = []
    with rosbag.Bag(sys.argv[1]) as bag:
        for connection_topic, raw, stamp in bag.read_messages(raw=True):
            datatype, data, md5sum, _position, pytype = raw
            message = pytype()
            message.deserialize(data)
            out.append({
                "topic": connection_topic,
                "datatype": datatype,
                "md5sum": md5sum,
                "genpy_md5sum": pytype._md5sum,
                "time_ns": stamp.to_nsec(),
                "message": plain(message, datatype),
            })
    with open(sys.argv[2], "w") as f:
        json.dump(out, f, allow_nan=False)


if __name__ == "__main__":
    main()
