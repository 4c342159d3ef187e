#!/usr/bin/python3
"""Named sensors as a user meets them (docs/sensors.md): a scenario with a stereo pair, an IMU and a
laser scanner drives, writes sensors/ with the documented columns, twice the same bytes; the IMU's
and the scanner's files checked from outside the code that made them (the exact gyroscope
integrated from the true start heading against ground_truth.tum; gravity at rest; the scanner's
noise against its exact ranges; every hit a world object); `run --export` writes the named cameras,
the scanner and TUM's accelerometer.txt; bad sensor input exits 2 naming the key.

usage: cli_sensors_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
"""

import csv
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import fail, fresh_folder, read, run  # noqa: E402

SCENARIO = """include: {source}/scenarios/default.yaml
world:
  length_m: 6.0
  doors: {{count: 2}}
  plates: {{count: 2}}
  distractors: {{posters: 1, notice_boards: 0, bookshelves: 0, cabinets: 0, fire_extinguishers: 1}}
duration_s: 16
sensors:
  left: {{type: camera, width: 80, height: 60, mount: {{x_m: 0.2, y_m: 0.06, z_m: 0.5}}}}
  right: {{type: camera, width: 80, height: 60, mount: {{x_m: 0.2, y_m: -0.06, z_m: 0.5}}}}
  imu0: {{type: imu, rate_hz: 1000, mount: {{x_m: 0.1, y_m: 0.05, z_m: 0.25}}}}
  scanner: {{type: laser, rate_hz: 10, range_sigma_m: 0.02}}
"""


def rows(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        return header, [r for r in reader]


def tum_yaw(path):
    """stamp (ns, from the nine decimals) -> planar heading."""
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            t, _x, _y, _z, qx, qy, qz, qw = line.split()
            whole, frac = t.split(".")
            stamp = int(whole) * 10**9 + int(frac)
            out[stamp] = math.atan2(2 * (float(qw) * float(qz) + float(qx) * float(qy)),
                                    1 - 2 * (float(qy) ** 2 + float(qz) ** 2))
    return out


def stamp_ns(text):
    whole, frac = text.split(".")
    return int(whole) * 10**9 + int(frac)


def check_imu(folder):
    header, data = rows(os.path.join(folder, "sensors", "imu0_imu.csv"))
    if header[:7] != ["t", "wx_rad_s", "wy_rad_s", "wz_rad_s", "ax_m_s2", "ay_m_s2", "az_m_s2"]:
        fail("imu0_imu.csv header: %s" % header[:7])
    col = {name: i for i, name in enumerate(header)}
    if len(data) != 16001:
        fail("imu0_imu.csv: %d samples, expected 16001 (1 kHz for 16 s, and 0)" % len(data))
    first = data[0]
    if [float(first[col[k]]) for k in ("true_ax_m_s2", "true_ay_m_s2", "true_az_m_s2")] != [0, 0, 9.81]:
        fail("the exact accelerometer at rest reads %s, not (0, 0, 9.81)" % first[10:13])
    # The exact z gyroscope integrated from the true start heading follows the truth's heading
    # (the IMU samples every physics step: each sample's rate turned the chassis over its step).
    truth = tum_yaw(os.path.join(folder, "ground_truth.tum"))
    yaw = truth[0]
    worst = 0.0
    previous = 0
    for r in data[1:]:
        t = stamp_ns(r[0])
        yaw += float(r[col["true_wz_rad_s"]]) * (t - previous) * 1e-9
        previous = t
        if t in truth:
            worst = max(worst, abs(math.remainder(yaw - truth[t], 2 * math.pi)))
    if worst > 2e-3:
        fail("the integrated gyroscope leaves the true heading by %.2e rad" % worst)
    turned = max(abs(math.remainder(v - truth[0], 2 * math.pi)) for v in truth.values())
    if turned < 1.0:
        fail("the drive turned only %.2f rad: the heading check needs a turn" % turned)
    print("ok: imu: 16001 samples; integrated gyroscope within %.1e rad of the truth's heading "
          "(the robot turned up to %.2f rad)" % (worst, turned))


def check_scanner(folder, world_ids):
    header, scans = rows(os.path.join(folder, "sensors", "scanner_scans.csv"))
    _, truth = rows(os.path.join(folder, "sensors", "scanner_scans_truth.csv"))
    _, hits = rows(os.path.join(folder, "sensors", "scanner_scans_hits.csv"))
    beams = len(header) - 7
    if beams != 361 or len(scans) != 160 or len(truth) != 160 or len(hits) != 160:
        fail("scanner: %d beams, %d/%d/%d sweeps; expected 361 beams, 160 sweeps"
             % (beams, len(scans), len(truth), len(hits)))
    errors = []
    for s, t, h in zip(scans, truth, hits):
        if not (s[0] == t[0] == h[0]):
            fail("scanner: sweeps out of step: %s %s %s" % (s[0], t[0], h[0]))
        for measured, exact, hit in zip(s[7:], t[15:], h[1:]):
            m, e = float(measured), float(exact)
            if math.isfinite(e) and int(hit) not in world_ids:
                fail("scanner: beam hit object %s, which world.json does not have" % hit)
            if math.isfinite(m) and 0.1 < e < 80:
                errors.append(m - e)
    n = len(errors)
    mean = sum(errors) / n
    sigma = math.sqrt(sum((x - mean) ** 2 for x in errors) / (n - 1))
    if n < 20000 or abs(mean) > 5 * 0.02 / math.sqrt(n) or abs(sigma / 0.02 - 1) > 0.03:
        fail("scanner: %d returns, error mean %.2e sigma %.4f (configured 0.02)" % (n, mean, sigma))
    print("ok: scanner: 160 sweeps of 361 beams; %d returns, noise mean %.1e m, sigma %.4f m "
          "(configured 0.02); every hit a world object" % (n, mean, sigma))


def check_euroc_imu(work):
    """--export's euroc/mav0/imu0/: EuRoC's data.csv (every sample the run folder has, as
    reported) and a sensor.yaml that a YAML reader takes, with Kalibr's noise keys and T_BS."""
    import yaml  # python3-yaml, as Kalibr and OpenVINS read their YAML
    folder = os.path.join(work, "export", "euroc", "mav0", "imu0")
    with open(os.path.join(folder, "data.csv")) as f:
        lines = f.read().splitlines()
    if not lines[0].startswith("#timestamp [ns],w_RS_S_x [rad s^-1]"):
        fail("imu0/data.csv header: " + lines[0])
    _, samples = rows(os.path.join(work, "run_sensors", "sensors", "imu0_imu.csv"))
    if len(lines) - 1 != len(samples):
        fail("imu0/data.csv has %d rows, the run folder %d samples" % (len(lines) - 1, len(samples)))
    for line, sample in zip(lines[1:], samples):
        values = line.split(",")
        if int(values[0]) != stamp_ns(sample[0]) or \
                any(abs(float(a) - float(b)) > 1e-7 * max(1.0, abs(float(b)))
                    for a, b in zip(values[1:], sample[1:7])):
            fail("imu0/data.csv row %s differs from the run's sample %s" % (line, sample[:7]))
    with open(os.path.join(folder, "sensor.yaml")) as f:
        sensor = yaml.safe_load(f)
    t_bs = sensor["T_BS"]["data"]
    if sensor["sensor_type"] != "imu" or sensor["rate_hz"] != 1000.0 or len(t_bs) != 16 or \
            abs(t_bs[3] - 0.1) > 1e-12 or abs(t_bs[7] - 0.05) > 1e-12 or \
            abs(t_bs[11] - 0.25) > 1e-12 or sensor["gyroscope_noise_density"] != 1.6968e-4:
        fail("imu0/sensor.yaml: %s" % sensor)
    # state_groundtruth_estimate0's biases: imu0's true ones at its latest sample before the row.
    header, truth = rows(os.path.join(work, "export", "euroc", "mav0",
                                      "state_groundtruth_estimate0", "data.csv"))
    bias_at = {stamp_ns(r[0]): [float(v) for v in r[13:19]] for r in samples}
    checked = 0
    for r in truth:
        t = int(r[0])
        previous = t - 1000000  # the 1 kHz sample before the row's stamp
        if previous in bias_at:
            if any(abs(float(a) - b) > 1e-9 for a, b in zip(r[11:17], bias_at[previous])):
                fail("state_groundtruth_estimate0 at %d: biases %s, imu0's %s" %
                     (t, r[11:17], bias_at[previous]))
            checked += 1
    if checked < 1000 or all(float(v) == 0 for v in truth[-1][11:17]):
        fail("state_groundtruth_estimate0: %d rows checked, last biases %s" % (checked, truth[-1][11:17]))
    print("ok: --export writes EuRoC's imu0/data.csv (%d samples, those of the run), sensor.yaml, "
          "and imu0's true biases in state_groundtruth_estimate0 (%d rows)" % (len(samples), checked))
    # The run folder's calibration files: Kalibr's imu.yaml keys, the scanner's geometry.
    sensors = os.path.join(work, "run_sensors", "sensors")
    with open(os.path.join(sensors, "imu0_imu.yaml")) as f:
        imu = yaml.safe_load(f)
    if imu != dict(sensor, comment=imu["comment"], rostopic="/imu0", update_rate=1000.0):
        fail("sensors/imu0_imu.yaml is not the export's sensor.yaml with Kalibr's keys: %s" % imu)
    with open(os.path.join(sensors, "scanner_laser.yaml")) as f:
        laser = yaml.safe_load(f)
    _, sweeps = rows(os.path.join(sensors, "scanner_scans.csv"))
    first = [float(v) for v in sweeps[0][1:7]]
    if laser["beams"] != 361 or abs(laser["angle_min"] - first[0]) > 1e-8 or \
            abs(laser["angle_increment"] - first[1]) > 1e-11 or laser["range_max"] != first[5] or \
            abs(laser["angle_max"] - math.pi / 2) > 1e-9 or laser["range_sigma"] != 0.02:
        fail("sensors/scanner_laser.yaml: %s against the sweeps' %s" % (laser, first))
    print("ok: sensors/ holds imu0_imu.yaml (Kalibr's keys) and scanner_laser.yaml (its geometry)")


def check_export_named(work):
    """--export's files of the named sensors (docs/export.md): the cameras beyond the three as
    euroc/mav0/cam2/, cam3/ in the scenario's order, named in cameras.yaml, each with its mount as
    T_BS and the pair at the same stamps; the scanner as laser0/ (every sweep of the run folder,
    the same numbers, and its geometry); imu0's accelerometer as TUM's accelerometer.txt."""
    import yaml
    mav = os.path.join(work, "export", "euroc", "mav0")
    with open(os.path.join(mav, "cameras.yaml")) as f:
        cameras = yaml.safe_load(f)
    if cameras != {"cam1": "lateral", "cam2": "left", "cam3": "right"}:
        fail("euroc/mav0/cameras.yaml: %s" % cameras)
    stamps = {}
    for cam, y in (("cam2", 0.06), ("cam3", -0.06)):
        with open(os.path.join(mav, cam, "sensor.yaml")) as f:
            sensor = yaml.safe_load(f)
        t_bs = sensor["T_BS"]["data"]
        if sensor["resolution"] != [80, 60] or [t_bs[3], t_bs[7], t_bs[11]] != [0.2, y, 0.5]:
            fail("%s/sensor.yaml: %s" % (cam, sensor))
        _, data = rows(os.path.join(mav, cam, "data.csv"))
        stamps[cam] = [r[0] for r in data]
        for r in data:
            if not os.path.isfile(os.path.join(mav, cam, "data", r[1])):
                fail("%s/data.csv names %s, which is not there" % (cam, r[1]))
    if stamps["cam2"] != stamps["cam3"] or len(stamps["cam2"]) < 40:
        fail("the pair's stamps differ: %s / %s" % (stamps["cam2"][:5], stamps["cam3"][:5]))
    if any(os.path.exists(os.path.join(mav, cam, "depth")) for cam in ("cam2", "cam3")):
        fail("a camera without depth has a depth/ folder")
    print("ok: --export writes left and right as cam2/ and cam3/ (cameras.yaml), %d frames each at "
          "the same stamps" % len(stamps["cam2"]))

    with open(os.path.join(mav, "laser0", "data.csv")) as f:
        lines = f.read().splitlines()
    if not lines[0].startswith("#timestamp [ns],angle_min [rad],angle_increment [rad],"
                               "time_increment [s],range_min [m],range_max [m],ranges [m]"):
        fail("laser0/data.csv header: " + lines[0])
    _, sweeps = rows(os.path.join(work, "run_sensors", "sensors", "scanner_scans.csv"))
    if len(lines) - 1 != len(sweeps) or len(sweeps) < 100:
        fail("laser0/data.csv has %d sweeps, the run folder %d" % (len(lines) - 1, len(sweeps)))
    for line, sweep in zip(lines[1:], sweeps):
        values = line.split(",")
        # The run folder's columns: t, angle_min, angle_increment, time_increment, scan_time,
        # range_min, range_max, ranges (the same text: nine significant digits, inf, nan).
        if int(values[0]) != stamp_ns(sweep[0]) or values[1:6] != sweep[1:4] + sweep[5:7] or \
                values[6:] != sweep[7:]:
            fail("laser0/data.csv row %s... differs from the run's sweep %s..." % (line[:80], sweep[:8]))
    if read(os.path.join(mav, "laser0", "sensor.yaml")) != \
            read(os.path.join(work, "run_sensors", "sensors", "scanner_laser.yaml")):
        fail("laser0/sensor.yaml is not the run folder's scanner_laser.yaml")
    print("ok: --export writes the scanner as laser0/: its %d sweeps and its geometry" % len(sweeps))

    with open(os.path.join(work, "export", "tum_rgbd", "accelerometer.txt")) as f:
        text = f.read().splitlines()
    if text[0] != "# accelerometer data" or text[2] != "# timestamp ax ay az":
        fail("tum_rgbd/accelerometer.txt header: %s" % text[:3])
    with open(os.path.join(mav, "imu0", "data.csv")) as f:
        imu = [line.split(",") for line in f.read().splitlines()[1:]]
    if len(text) - 3 != len(imu):
        fail("accelerometer.txt has %d rows, imu0 %d samples" % (len(text) - 3, len(imu)))
    for line, sample in zip(text[3:], imu):
        t, ax, ay, az = line.split(" ")
        if stamp_ns(t) != int(sample[0]) or [ax, ay, az] != sample[4:7]:
            fail("accelerometer.txt row %s is not imu0's sample %s" % (line, sample))
    print("ok: tum_rgbd/accelerometer.txt holds imu0's %d accelerometer samples (its own frame)"
          % len(imu))


def world_ids(folder):
    with open(os.path.join(folder, "world.json")) as f:
        world = json.load(f)
    ids = set()

    def walk(node):
        if isinstance(node, dict):
            if isinstance(node.get("id"), int):
                ids.add(node["id"])
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)
    walk(world)
    return ids


def main():
    binary, source, work = sys.argv[1], sys.argv[2], fresh_folder(sys.argv[3])
    scenario = os.path.join(work, "sensors.yaml")
    with open(scenario, "w") as f:
        f.write(SCENARIO.format(source=source))
    for name in ("a", "b"):
        run(binary, ["drive", scenario, "--out", os.path.join(work, name)], 0, work)
    for f in sorted(os.listdir(os.path.join(work, "a", "sensors"))):
        if read(os.path.join(work, "a", "sensors", f)) != read(os.path.join(work, "b", "sensors", f)):
            fail("sensors/%s differs between two drives of one scenario and seed" % f)
    print("ok: two drives wrote the same sensors/ bytes")
    # world.json comes with `corridorsim world` of the same scenario.
    run(binary, ["world", scenario, "--out", os.path.join(work, "world")], 0, work)
    check_imu(os.path.join(work, "a"))
    shutil.copy(os.path.join(work, "world", "ground_truth.json"), os.path.join(work, "a", "world.json"))
    check_scanner(os.path.join(work, "a"), world_ids(os.path.join(work, "a")))

    # A run's pipelines receive the new sensors' messages, and adding sensors changes no other
    # stream: the same metrics.json with and without them.
    plain = os.path.join(work, "plain.yaml")
    with open(plain, "w") as f:
        f.write(SCENARIO.format(source=source).split("sensors:")[0])
    args = ["--no-plots", "--no-viewer", "--set", "pipelines.p1_harris.enabled=false", "--set",
            "pipelines.p1_vp_doorplate.enabled=false", "--set", "expectations=[]"]
    run(binary, ["run", scenario, "--out", os.path.join(work, "run_sensors"), "--export",
                 os.path.join(work, "export")] + args, 0, work)
    run(binary, ["run", plain, "--out", os.path.join(work, "run_plain")] + args, 0, work)
    if read(os.path.join(work, "run_sensors", "metrics.json")) != \
            read(os.path.join(work, "run_plain", "metrics.json")):
        fail("metrics.json differs with the IMU and the scanner added")
    if not os.path.exists(os.path.join(work, "run_sensors", "sensors", "imu0_imu.csv")):
        fail("a run wrote no sensors/imu0_imu.csv")
    print("ok: a run with the sensors writes sensors/ and the metrics of the run without them")
    # The run folder's scenario.yaml names the new sensors' kinds: it repeats the run.
    again = os.path.join(work, "run_again")
    run(binary, ["run", os.path.join(work, "run_sensors", "scenario.yaml"), "--out", again,
                 "--no-plots", "--no-viewer"], 0, work)
    for f in sorted(os.listdir(os.path.join(work, "run_sensors", "sensors"))) + ["../metrics.json"]:
        if read(os.path.join(work, "run_sensors", "sensors", f)) != \
                read(os.path.join(again, "sensors", f)):
            fail("the run repeated from its scenario.yaml differs in sensors/%s" % f)
    print("ok: the run's scenario.yaml repeats it: the same sensors/ and metrics.json")
    check_euroc_imu(work)
    check_export_named(work)

    bad = [
        ("imu_rate", "  imu0: {type: imu, rate_hz: 300}\n", "sensors.imu0.rate_hz"),
        ("imu_phase", "  imu0: {type: imu, phase_s: 0.0005}\n", "sensors.imu0.phase_s"),
        ("imu_density", "  imu0: {type: imu, gyroscope_noise_density: -1}\n",
         "sensors.imu0.gyroscope_noise_density"),
        ("laser_angles", "  s: {type: laser, angle_min_deg: 10, angle_max_deg: 5}\n",
         "sensors.s.angle_max_deg"),
        ("laser_beams", "  s: {type: laser, resolution_deg: 0.01, angle_min_deg: -180, "
         "angle_max_deg: 180}\n", "sensors.s."),
        ("laser_key", "  s: {type: laser, beams: 10}\n", "sensors.s.beams"),
        ("no_type", "  s: {rate_hz: 10}\n", "sensors.s"),
        ("bad_type", "  s: {type: sonar}\n", "sensors.s.type"),
        ("type_changed", "  front: {type: laser}\n", "sensors.front.type"),
        ("bad_name", "  Scan-1: {type: laser}\n", "sensors.Scan-1"),
        # A scanner inside the chassis, or one that meets a wall along the path.
        ("laser_in_chassis", "  s: {type: laser, mount: {x_m: 0, z_m: 0.15}}\n", "sensors.s.mount"),
        ("laser_in_wall", "  s: {type: laser, mount: {y_m: 1.4, z_m: 0.5}}\n", "sensors.s.mount"),
        # An IMU's period is held against the physics step only once the rate is valid.
        ("physics_zero", "  imu0: {type: imu}\nrobot: {physics_rate_hz: 0}\n",
         "robot.physics_rate_hz"),
        ("physics_huge", "  imu0: {type: imu}\nrobot: {physics_rate_hz: 1e300}\n",
         "robot.physics_rate_hz"),
    ]
    for name, yaml, key in bad:
        path = os.path.join(work, name + ".yaml")
        with open(path, "w") as f:
            f.write("include: %s/scenarios/default.yaml\nsensors:\n%s" % (source, yaml))
        result = run(binary, ["drive", path, "--out", os.path.join(work, "bad_" + name)], 2, work)
        if (name + ".yaml:") not in result.stderr or key not in result.stderr:
            fail("%s: the message does not name the file and %s:\n%s" % (name, key, result.stderr))
    print("ok: %d kinds of bad sensor input exit 2 naming the file and key" % len(bad))


if __name__ == "__main__":
    main()
