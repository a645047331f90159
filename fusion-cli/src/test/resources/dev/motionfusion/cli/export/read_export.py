"""Reads a fusion export back with the external readers and prints what they found, one row a line.

  read_export.py euroc MAV0_FOLDER   evo: the orientation with evo's EuRoC trajectory reader
                                     (file_interface.read_euroc_csv_trajectory), imu0 and mag0
                                     with evo's CSV reader (file_interface.csv_read_matrix)
  read_export.py kalibr FOLDER       imu0.csv as kalibr_bagcreater parses it (csv module, the
                                     time string split into s and ns, float values), imu.yaml with PyYAML as kalibr loads it
  read_export.py ros2 FILE.mcap      the MCAP file with the mcap package through its summary and
                                     chunk indexes (log-time order, chunk CRCs checked) and
                                     mcap-ros2-support's CDR decoder, again from start to end (data
                                     section and chunk CRCs checked), again with rosbags (AnyReader);
                                     its chunks, message indexes, summary offsets and summary CRC
                                     walked byte by byte; each channel's offered_qos_profiles with
                                     PyYAML and as rosbags parses it
  read_export.py configs FOLDER      fusion allan's noise configurations with OpenCV's FileStorage
                                     (cv2), the reader OpenVINS, VINS and ORB-SLAM3 load them with,
                                     and imu.yaml with PyYAML as kalibr loads it

Output lines: "<table> <field> ..." with every number as Python's repr (the shortest decimal
that reads back to the same double), so the caller can compare them to the last digit.
"""
import csv
import os
import sys


def euroc(mav0):
    from evo.tools import file_interface as fi
    traj = fi.read_euroc_csv_trajectory(os.path.join(mav0, "state_groundtruth_estimate0", "data.csv"))
    print("pose", len(traj.timestamps))
    for t, p, q in zip(traj.timestamps, traj.positions_xyz, traj.orientations_quat_wxyz):
        print("pose_row", repr(float(t)), *(repr(float(v)) for v in q), *(repr(float(v)) for v in p))
    for table in ("imu0", "mag0"):
        path = os.path.join(mav0, table, "data.csv")
        if not os.path.exists(path):
            continue
        rows = fi.csv_read_matrix(path, delim=",", comment_str="#")
        print(table, len(rows))
        for r in rows:
            print(table + "_row", int(r[0]), *(repr(float(v)) for v in r[1:]))


def kalibr(folder):
    import yaml
    with open(os.path.join(folder, "imu0.csv"), newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    print("header", ",".join(header))
    print("imu0", len(rows))
    for r in rows:
        # As kalibr_bagcreater: the seconds are all but the last nine digits, the nanoseconds those nine.
        ns = int(r[0][0:-9]) * 1000000000 + int(r[0][-9:])
        print("imu0_row", ns, *(repr(float(v)) for v in r[1:7]))
    with open(os.path.join(folder, "imu.yaml")) as f:
        conf = yaml.safe_load(f)
    for k in sorted(conf):
        print("yaml", k, repr(conf[k]))


def ros2(path):
    import yaml
    from pathlib import Path
    from mcap.reader import NonSeekingReader, make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        if summary is None or summary.statistics is None or not summary.chunk_indexes:
            raise SystemExit("no summary with statistics and chunk indexes: the file is not indexed")
        s = summary.statistics
        print("statistics", s.message_count, s.schema_count, s.channel_count, s.chunk_count, s.message_start_time, s.message_end_time)
        for cid, n in sorted(s.channel_message_counts.items()):
            print("statistics_channel", summary.channels[cid].topic, n)
        for channel in summary.channels.values():
            profiles = yaml.safe_load(channel.metadata["offered_qos_profiles"])
            print("qos_profiles", channel.topic, len(profiles))
            print("qos_keys", channel.topic, *profiles[0].keys())
            for k, v in profiles[0].items():
                print("qos", channel.topic, k, "%d/%d" % (v["sec"], v["nsec"]) if isinstance(v, dict) else repr(v))
        # Through the chunk indexes (the file has a summary), in log-time order.
        for _, channel, message, m in reader.iter_decoded_messages(log_time_order=True):
            print("indexed", channel.topic, message.sequence, message.log_time)
            ros2_row("mcap", channel.topic, message.log_time, m)
    with open(path, "rb") as f:
        n = sum(1 for _ in NonSeekingReader(f, validate_crcs=True).iter_messages())
        print("streamed", n)
    mcap_layout(Path(path).read_bytes(), summary)
    with AnyReader([Path(path)]) as reader:
        for connection in reader.connections:
            for q in connection.ext.offered_qos_profiles:
                print("rosbags_qos", connection.topic, q.history.name, q.depth, q.reliability.name, q.durability.name,
                      q.liveliness.name, q.avoid_ros_namespace_conventions)
        for connection, t, raw in reader.messages():
            ros2_row("rosbags", connection.topic, t, reader.deserialize(raw, connection.msgtype))


def mcap_layout(data, summary):
    """Walks the file's bytes: each chunk against its Chunk Index (one "chunk" line: index, messages,
    record bytes, "ok" or the failed checks) and its Message Index records (right after it, one per
    channel, each entry the log time and offset of a message of that channel, all of them once); the
    Summary Offset groups and the footer's summary CRC (one "summary" line)."""
    import struct
    import zlib
    for k, ci in enumerate(summary.chunk_indexes):
        o = ci.chunk_start_offset
        op, length = struct.unpack_from("<BQ", data, o)
        start, end, size, crc, n = struct.unpack_from("<QQQII", data, o + 9)
        compression = data[o + 41:o + 41 + n].decode()
        (records_length,) = struct.unpack_from("<Q", data, o + 41 + n)
        records = data[o + 49 + n:o + 49 + n + records_length]
        messages, p = {}, 0
        while p < len(records):
            rop, rlength = struct.unpack_from("<BQ", records, p)
            if rop == 0x05:
                channel, sequence, log_time = struct.unpack_from("<HIQ", records, p + 9)
                messages[p] = (channel, log_time)
            p += 9 + rlength
        indexed, offsets, sorted_index, q = {}, {}, True, o + ci.chunk_length
        while q < o + ci.chunk_length + ci.message_index_length:
            iop, ilength = struct.unpack_from("<BQ", data, q)
            channel, n = struct.unpack_from("<HI", data, q + 9)
            offsets[channel] = q
            times = []
            for j in range(n // 16):
                log_time, offset = struct.unpack_from("<QQ", data, q + 15 + 16 * j)
                indexed.setdefault(offset, []).append((channel, log_time))
                times.append(log_time)
            sorted_index &= iop == 0x07 and times == sorted(times)
            q += 9 + ilength
        logs = [t for _, t in messages.values()]
        checks = [
            ("opcode", op == 0x06 and 9 + length == ci.chunk_length),
            ("records", p == len(records) == records_length),
            ("compression", compression == ci.compression == ""),
            ("sizes", size == records_length == ci.uncompressed_size == ci.compressed_size),
            ("crc", crc == zlib.crc32(records)),
            ("times", bool(logs) and start == ci.message_start_time == min(logs) and end == ci.message_end_time == max(logs)),
            ("index_offsets", offsets == ci.message_index_offsets and q == o + ci.chunk_length + ci.message_index_length),
            ("index_entries", sorted_index and indexed == {p: [m] for p, m in messages.items()}),
        ]
        print("chunk", k, len(messages), records_length, ",".join(c for c, good in checks if not good) or "ok")
    footer = len(data) - 8 - 29
    op, length, summary_start, summary_offset_start, summary_crc = struct.unpack_from("<BQQQI", data, footer)
    groups, p = [], summary_offset_start
    while p < footer:
        sop, slength, group, group_start, group_length = struct.unpack_from("<BQBQQ", data, p)
        ops, q = set(), group_start
        while q < group_start + group_length:
            rop, rlength = struct.unpack_from("<BQ", data, q)
            ops.add(rop)
            q += 9 + rlength
        groups.append("%02x:%s" % (group, "ok" if sop == 0x0E and ops == {group} and q == group_start + group_length else "bad"))
        p += 9 + slength
    crc_ok = op == 0x02 and summary_crc == zlib.crc32(data[summary_start:footer + 25])
    print("summary", "crc_ok" if crc_ok else "crc_bad", *groups)


def ros2_row(reader, topic, log_time, m):
    """One message: log time, stamp, frame_id, the values, the covariances' first entry, the largest magnitude
    off their diagonals, then the diagonals of the angular velocity and linear acceleration covariances
    (of the magnetic field's on /imu/mag)."""
    if topic == "/imu/mag":
        values = [m.magnetic_field.x, m.magnetic_field.y, m.magnetic_field.z]
        covariances = [list(m.magnetic_field_covariance)]
        diagonals = [list(m.magnetic_field_covariance)]
    else:
        q, w, a = m.orientation, m.angular_velocity, m.linear_acceleration
        values = [q.w, q.x, q.y, q.z, w.x, w.y, w.z, a.x, a.y, a.z]
        covariances = [list(m.orientation_covariance), list(m.angular_velocity_covariance), list(m.linear_acceleration_covariance)]
        diagonals = covariances[1:]
    first = [c[0] for c in covariances]
    off = max(abs(v) for c in covariances for i, v in enumerate(c) if i not in (0, 4, 8))
    diagonal = [c[i] for c in diagonals for i in (0, 4, 8)]
    print(reader + ":" + topic, log_time, m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id,
          *(repr(float(v)) for v in values + first + [off] + diagonal))


def configs(folder):
    import cv2
    import yaml
    with open(os.path.join(folder, "imu.yaml")) as f:
        for k, v in sorted(yaml.safe_load(f).items()):
            print("kalibr", k, repr(v))
    for name, keys in (("kalibr_imu_chain.yaml", None),
                       ("vins_imu.yaml", ["acc_n", "gyr_n", "acc_w", "gyr_w"]),
                       ("orbslam3_imu.yaml", ["IMU.NoiseGyro", "IMU.NoiseAcc", "IMU.GyroWalk", "IMU.AccWalk", "IMU.Frequency"])):
        fs = cv2.FileStorage(os.path.join(folder, name), cv2.FILE_STORAGE_READ)
        if not fs.isOpened():
            raise SystemExit("cv2.FileStorage cannot open " + name)
        if keys is None:
            node = fs.getNode("imu0")
            for k in node.keys():
                n = node.getNode(k)
                if n.isString():
                    print(name, k, n.string())
                elif n.isSeq():
                    print(name, k, *(repr(float(n.at(i).at(j).real())) for i in range(n.size()) for j in range(n.at(i).size())))
                else:
                    print(name, k, repr(float(n.real())))
        else:
            for k in keys:
                n = fs.getNode(k)
                if n.empty():
                    raise SystemExit(name + ": no " + k)
                print(name, k, repr(float(n.real())))
        fs.release()


if __name__ == "__main__":
    {"euroc": euroc, "kalibr": kalibr, "ros2": ros2, "configs": configs}[sys.argv[1]](sys.argv[2])
