package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.BeforeAll
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.TestInstance
import org.junit.jupiter.api.io.TempDir
import dev.motionfusion.core.export.NoiseModel
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.concurrent.TimeUnit

/**
 * Each `fusion export` format read back by the tool it is for: EuRoC by evo (PyPI), Kalibr's
 * imu0.csv and imu.yaml as kalibr_bagcreater and kalibr parse them (Python csv, PyYAML), gcsv by
 * Gyroflow's telemetry-parser crate (built with cargo), the ROS 2 MCAP file by the mcap package with
 * mcap-ros2-support's CDR decoder and by rosbags. Every row is compared with what the replay
 * stepped on (`fusion replay --rows`), its orientation and the session's own timestamps: the count,
 * the first and last timestamps and every value, as doubles parsed from both sides (to the last
 * digit). A reader that cannot be installed skips its test with the reason.
 */
@TestInstance(TestInstance.Lifecycle.PER_CLASS)
class ExportReadersTest {
    private lateinit var dir: Path

    private lateinit var session: Path
    /** The session's gyroscope timestamps, ns: the export's rows. */
    private lateinit var times: List<Long>
    /** `fusion replay --rows`: gx..az, mx..mz as written, one per gyroscope sample. */
    private lateinit var rows: List<List<String>>
    /** The replay's qw, qx, qy, qz per row. */
    private lateinit var quaternions: List<List<String>>
    /** The session's magnetometer: timestamp ns, x, y, z. */
    private lateinit var magnetometer: List<List<String>>

    @BeforeAll
    fun recording(@TempDir temp: Path) {
        dir = temp
        session = dir.resolve("walk")
        assertEquals(ExitCode.OK, fusion("simulate", "-o", session.toString(), "--duration", "6", "--seed", "3").code)
        val r = fusion("replay", session.toString(), "-o", dir.resolve("replay.csv").toString(), "--rows", dir.resolve("rows.csv").toString(), "--quiet")
        assertEquals(ExitCode.OK, r.code, r.err)
        times = csv(session.resolve("gyroscope.csv")).map { it[0].toLong() }
        rows = csv(dir.resolve("rows.csv")).map { it.drop(1) }
        quaternions = csv(dir.resolve("replay.csv")).map { it.subList(1, 5) }
        magnetometer = csv(session.resolve("magnetometer.csv")).map { it.take(4) }
        assertEquals(times.size, rows.size)
        assertTrue(times.size > 500)
    }

    @Test
    fun `euroc read back by evo`() {
        val out = dir.resolve("euroc")
        val r = fusion("export", session.toString(), "--format", "euroc", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertEquals("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]", Files.readAllLines(out.resolve("mav0/imu0/data.csv"))[0])
        // EuRoC's ground truth has 17 columns, and readers that take all of them (Kimera-VIO's) read 17 fields a row
        // whatever the file holds: position, velocity and the biases are not estimated, so 0.
        val truth = Files.readAllLines(out.resolve("mav0/state_groundtruth_estimate0/data.csv"))
        assertEquals(17, truth[0].split(',').size, truth[0])
        assertEquals(times.size, truth.size - 1, "ground-truth rows")
        for (line in truth.drop(1)) {
            val f = line.split(',')
            assertEquals(17, f.size, line)
            for (c in (1..3) + (8..16)) assertEquals(0.0, f[c].toDouble(), "column $c of $line")
        }
        val read = python("euroc", out.resolve("mav0"), "evo")
        // Orientation: evo's trajectory (seconds as ns / 1e9, quaternion w x y z, position).
        val pose = read.getValue("pose_row")
        assertEquals(times.size, pose.size, "orientation rows")
        for ((k, p) in pose.withIndex()) {
            assertEquals(times[k] / 1e9, p[0].toDouble(), "pose $k time")
            for (c in 0 until 4) assertEquals(quaternions[k][c].toDouble(), p[1 + c].toDouble(), "pose $k q$c")
            for (c in 5 until 8) assertEquals(0.0, p[c].toDouble())
        }
        // IMU: evo's CSV reader, every row.
        val imu = read.getValue("imu0_row")
        assertEquals(times.size, imu.size, "imu rows")
        for ((k, row) in imu.withIndex()) {
            assertEquals(times[k], row[0].toLong(), "imu $k time")
            for (c in 0 until 6) assertEquals(rows[k][c].toDouble(), row[1 + c].toDouble(), "imu $k column ${c + 1}")
        }
        // Magnetometer at its own times.
        val mag = read.getValue("mag0_row")
        assertEquals(magnetometer.size, mag.size, "magnetometer rows")
        for ((k, row) in mag.withIndex()) {
            assertEquals(magnetometer[k][0].toLong(), row[0].toLong())
            for (c in 1..3) assertEquals(magnetometer[k][c].toDouble(), row[c].toDouble(), "mag $k column $c")
        }
        println("euroc via evo: ${pose.size} poses, ${imu.size} IMU rows, ${mag.size} magnetometer rows; " +
            "first/last ${imu.first()[0]}/${imu.last()[0]} ns; every value equal")
    }

    @Test
    fun `kalibr read back as kalibr_bagcreater and kalibr parse it`() {
        val noise = noiseModel("noise.yaml")
        val out = dir.resolve("kalibr")
        val r = fusion("export", session.toString(), "--format", "kalibr", "--noise", noise.toString(), "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val read = python("kalibr", out, "yaml")
        assertEquals("timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z", read.getValue("header").single()[0])
        val imu = read.getValue("imu0_row")
        assertEquals(times.size, imu.size)
        for ((k, row) in imu.withIndex()) {
            assertEquals(times[k], row[0].toLong(), "imu $k time")
            for (c in 0 until 6) assertEquals(rows[k][c].toDouble(), row[1 + c].toDouble(), "imu $k column ${c + 1}")
        }
        val yaml = read.getValue("yaml").associate { it[0] to it[1] }
        // The noise file says 100 Hz; kalibr discretises at update_rate, which is the rows' own.
        val rate = (times.size - 1) * 1e9 / (times.last() - times.first())
        assertEquals(rate, yaml.getValue("update_rate").toDouble(), 0.0005, "update_rate: the rows' rate")
        assertEquals("0.00017", yaml["gyroscope_noise_density"])
        assertEquals("2.1e-05", yaml["gyroscope_random_walk"])
        assertEquals("'/imu0'", yaml["rostopic"])
        println("kalibr via csv/PyYAML: ${imu.size} rows, first/last ${imu.first()[0]}/${imu.last()[0]} ns; every value equal; imu.yaml keys ${yaml.keys}")
    }

    @Test
    fun `gcsv read back by telemetry-parser`() {
        val reader = gcsvReader()
        val out = dir.resolve("walk.gcsv")
        val r = fusion("export", session.toString(), "--format", "gcsv", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val p = run(listOf(reader.toString(), out.toString()), dir, 120)
        assertEquals(0, p.first, p.third)
        val read = parse(p.second)
        assertEquals("motion_fusion", read.getValue("camera").single()[0])
        for ((name, from, scale) in listOf(Triple("gyro", 0, Math.PI / 180), Triple("accl", 3, 9.80665), Triple("magn", 6, 10000.0))) {
            val head = read.getValue(name).single()
            assertEquals(times.size, head[0].toInt(), "$name samples")
            assertEquals(scale, head[1].toDouble(), 1e-12 * scale, "$name scale")
            assertEquals("XYZ", head[2])
            val samples = read.getValue("${name}_row")
            for ((k, s) in samples.withIndex()) {
                // telemetry-parser: t = raw t × tscale (1e-9), the same double operation here.
                assertEquals(times[k].toDouble() * 1e-9, s[0].toDouble(), "$name $k time")
                for (c in 0 until 3) assertEquals(rows[k][from + c].toDouble(), s[1 + c].toDouble(), "$name $k axis $c")
            }
        }
        println("gcsv via telemetry-parser: ${times.size} samples of gyro, accl, magn; first/last ${times.first() * 1e-9}/${times.last() * 1e-9} s; every value equal")
    }

    @Test
    fun `ros2 read back by mcap with mcap-ros2-support and by rosbags`() {
        val out = dir.resolve("walk.mcap")
        val r = fusion("export", session.toString(), "--format", "ros2", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val read = python("ros2", out, "mcap_ros2.decoder, rosbags.highlevel, yaml")
        for (reader in listOf("mcap", "rosbags")) {
            for (topic in listOf("/imu/data_raw", "/imu/data")) {
                val messages = read.getValue("$reader:$topic")
                assertEquals(times.size, messages.size, "$reader $topic messages")
                for ((k, m) in messages.withIndex()) {
                    stamp(times[k], m, "$reader $topic $k")
                    assertEquals("imu_link", m[3])
                    val v = m.drop(4).map { it.toDouble() }
                    if (topic == "/imu/data") {
                        // The replay's CSV has the quaternion to 9 decimals; the message its full double.
                        for (c in 0 until 4) assertEquals(quaternions[k][c].toDouble(), v[c], 5e-10, "$reader $topic $k q$c")
                    } else {
                        for (c in 0 until 4) assertEquals(0.0, v[c])
                    }
                    // Gyroscope and accelerometer: the recorded float, exactly.
                    for (c in 0 until 6) assertEquals(rows[k][c].toFloat().toDouble(), v[4 + c], "$reader $topic $k value $c")
                    assertEquals(if (topic == "/imu/data_raw") -1.0 else 0.0, v[10], "orientation_covariance[0] (REP-145: -1 = not provided)")
                    // No noise model: the covariances unknown, zeros.
                    assertEquals(0.0, v[11]); assertEquals(0.0, v[12]); assertEquals(0.0, v[13])
                    for (c in 14 until 20) assertEquals(0.0, v[c], "$reader $topic $k covariance diagonal")
                }
            }
            val mag = read.getValue("$reader:/imu/mag")
            assertEquals(magnetometer.size, mag.size, "$reader magnetometer messages")
            for ((k, m) in mag.withIndex()) {
                stamp(magnetometer[k][0].toLong(), m, "$reader mag $k")
                // Tesla: the recorded µT float × 1e-6, the same double operation here.
                for (c in 0 until 3) assertEquals(magnetometer[k][1 + c].toFloat().toDouble() * 1e-6, m[4 + c].toDouble(), "$reader mag $k axis $c")
            }
        }
        val chunks = indexed(read, mapOf("/imu/data_raw" to times, "/imu/data" to times, "/imu/mag" to magnetometer.map { it[0].toLong() }))
        println("ros2 via mcap+mcap-ros2-support and rosbags: ${times.size} /imu/data_raw, ${times.size} /imu/data, ${magnetometer.size} /imu/mag messages each; " +
            "first/last ${times.first()}/${times.last()} ns; every value equal (quaternion within the replay CSV's 9 decimals); " +
            "$chunks chunk(s) with message indexes, statistics and summary as written, CRCs valid; offered_qos_profiles: sensor data (keep last 5, best effort, volatile)")
    }

    @Test
    fun `ros2 covariances from a noise model, read back by mcap and rosbags`() {
        val noise = noiseModel("noise-ros2.yaml")
        val out = dir.resolve("walk-noise.mcap")
        val r = fusion("export", session.toString(), "--format", "ros2", "--noise", noise.toString(), "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val read = python("ros2", out, "mcap_ros2.decoder, rosbags.highlevel, yaml")
        // One sample's white-noise variance N²·f at the gyroscope's mean rate f, on the diagonal.
        val f = (times.size - 1) * 1e9 / (times.last() - times.first())
        val gyro = 0.00017 * 0.00017 * f
        val acc = 0.0012 * 0.0012 * f
        assertTrue(gyro > 0 && acc > 0)
        for (reader in listOf("mcap", "rosbags")) {
            for (topic in listOf("/imu/data_raw", "/imu/data")) {
                val messages = read.getValue("$reader:$topic")
                assertEquals(times.size, messages.size, "$reader $topic messages")
                for ((k, m) in messages.withIndex()) {
                    val v = m.drop(4).map { it.toDouble() }
                    assertEquals(if (topic == "/imu/data_raw") -1.0 else 0.0, v[10], "orientation_covariance[0]")
                    assertEquals(0.0, v[13], "$reader $topic $k off the diagonals")
                    for (c in 14 until 17) assertEquals(gyro, v[c], "$reader $topic $k angular_velocity_covariance diagonal")
                    for (c in 17 until 20) assertEquals(acc, v[c], "$reader $topic $k linear_acceleration_covariance diagonal")
                }
            }
            // The magnetometer has no noise model: unknown.
            for (m in read.getValue("$reader:/imu/mag")) for (c in 3 until 8) assertEquals(0.0, m[4 + c].toDouble())
        }
        indexed(read, mapOf("/imu/data_raw" to times, "/imu/data" to times, "/imu/mag" to magnetometer.map { it[0].toLong() }))
        println("ros2 covariances via mcap and rosbags: angular velocity $gyro rad²/s², linear acceleration $acc m²/s⁴ at f = $f Hz on every message")
    }

    @Test
    fun `ros2 over several chunks, every message read back once and in order`(@TempDir temp: Path) {
        // 40 s: about 3.5 MB of messages, so several chunks of 1 MiB.
        val long = temp.resolve("long")
        assertEquals(ExitCode.OK, fusion("simulate", "-o", long.toString(), "--duration", "40", "--seed", "5").code)
        val gyroscope = csv(long.resolve("gyroscope.csv")).map { it[0].toLong() }
        val field = csv(long.resolve("magnetometer.csv")).map { it[0].toLong() }
        val out = temp.resolve("long.mcap")
        val r = fusion("export", long.toString(), "--format", "ros2", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val read = python("ros2", out, "mcap_ros2.decoder, rosbags.highlevel, yaml")
        // /imu/data starts at the filter's first orientation: the last of the gyroscope's times.
        val oriented = read.getValue("mcap:/imu/data").size
        assertTrue(oriented > gyroscope.size - 100, "/imu/data messages: $oriented of ${gyroscope.size}")
        val expected = mapOf("/imu/data_raw" to gyroscope, "/imu/data" to gyroscope.takeLast(oriented), "/imu/mag" to field)
        val chunks = indexed(read, expected)
        assertTrue(chunks >= 3, "chunks: $chunks")
        // Both readers: every message of each topic once, at its time, in order across the chunks' boundaries.
        for (reader in listOf("mcap", "rosbags")) for ((topic, t) in expected) {
            assertEquals(t, read.getValue("$reader:$topic").map { it[0].toLong() }, "$reader $topic log times")
            assertEquals(t, read.getValue("$reader:$topic").map { it[1].toLong() * 1_000_000_000L + it[2].toLong() }, "$reader $topic stamps")
        }
        val sizes = read.getValue("chunk").map { it[2].toLong() }
        assertTrue(sizes.dropLast(1).all { it in (1L shl 20) until (1L shl 20) + 4096 }, "chunk record sizes $sizes: closed at 1 MiB")
        println("ros2 over ${chunks} chunks (record bytes $sizes): ${expected.values.sumOf { it.size }} messages " +
            "(${gyroscope.size} /imu/data_raw, $oriented /imu/data, ${field.size} /imu/mag), each once and in log-time order by mcap's index and by rosbags")
    }

    /**
     * The MCAP file's index and summary as [read] found them, against [expected] log times per topic:
     * Statistics (counts, first and last time, per channel), every chunk's checks ("ok": CRC, sizes,
     * times, message indexes pointing at each of its messages once), the summary's CRC and offset
     * groups, all messages again from start to end with the data section's CRC, the indexed read in
     * log-time order with each channel's sequence 0, 1, 2 … once; offered_qos_profiles as PyYAML and
     * rosbags read it. Returns the number of chunks.
     */
    private fun indexed(read: Map<String, List<List<String>>>, expected: Map<String, List<Long>>): Int {
        val total = expected.values.sumOf { it.size }
        val all = expected.values.flatten()
        val statistics = read.getValue("statistics").single().map { it.toLong() }
        val chunks = read.getValue("chunk")
        assertEquals(listOf(total.toLong(), 2L, 3L, chunks.size.toLong(), all.min(), all.max()), statistics, "statistics: messages, schemas, channels, chunks, first, last")
        assertEquals(expected.mapValues { it.value.size.toString() }, read.getValue("statistics_channel").associate { it[0] to it[1] }, "statistics per channel")
        for (c in chunks) assertEquals("ok", c[3], "chunk ${c[0]}: failed ${c[3]}")
        assertEquals(total, chunks.sumOf { it[1].toInt() }, "messages in the chunks")
        assertEquals(listOf("crc_ok", "03:ok", "04:ok", "0b:ok", "08:ok"), read.getValue("summary").single(), "summary CRC and offset groups")
        assertEquals(total, read.getValue("streamed").single()[0].toInt(), "messages read from start to end")
        val order = read.getValue("indexed")
        assertEquals(total, order.size, "messages through the index")
        for (k in 1 until order.size) assertTrue(order[k][2].toLong() >= order[k - 1][2].toLong(), "indexed message $k before its predecessor: ${order[k]} after ${order[k - 1]}")
        for ((topic, t) in expected) assertEquals((0 until t.size).map { it.toString() }, order.filter { it[0] == topic }.map { it[1] }, "$topic sequence numbers")
        // offered_qos_profiles: one profile, rosbag2's keys, rmw_qos_profile_sensor_data's values.
        val keys = listOf("history", "depth", "reliability", "durability", "deadline", "lifespan", "liveliness", "liveliness_lease_duration", "avoid_ros_namespace_conventions")
        val values = listOf("1", "5", "2", "2", "0/0", "0/0", "0", "0/0", "False")
        for (topic in expected.keys) {
            assertEquals(listOf(topic, "1"), read.getValue("qos_profiles").single { it[0] == topic }, "$topic profiles")
            assertEquals(listOf(topic) + keys, read.getValue("qos_keys").single { it[0] == topic })
            assertEquals(keys.zip(values).toMap(), read.getValue("qos").filter { it[0] == topic }.associate { it[1] to it[2] }, "$topic offered_qos_profiles")
            assertEquals(listOf(topic, "KEEP_LAST", "5", "BEST_EFFORT", "VOLATILE", "SYSTEM_DEFAULT", "False"), read.getValue("rosbags_qos").single { it[0] == topic }, "$topic QoS as rosbags parses it")
        }
        return chunks.size
    }

    /** A noise model as fusion allan writes it (N_a 0.0012, K_a 0.0003, N_g 0.00017, K_g 2.1e-05) in [name]. */
    private fun noiseModel(name: String): Path = dir.resolve(name).also {
        Files.writeString(it, "accelerometer_noise_density: 0.0012\naccelerometer_random_walk: 0.0003\n" +
            "gyroscope_noise_density: 0.00017\ngyroscope_random_walk: 2.1e-05\nrostopic: /imu0\nupdate_rate: 100\n")
    }

    /** Log time and header stamp of a message line both [ns]. */
    private fun stamp(ns: Long, m: List<String>, what: String) {
        assertEquals(ns, m[0].toLong(), "$what log time")
        assertEquals(ns, m[1].toLong() * 1_000_000_000L + m[2].toLong(), "$what header stamp")
    }

    @Test
    fun `allan's noise configurations read by the stacks' reader, each with its conversion`() {
        // 120 s still at 100 Hz with white noise of known density (σd = N·√f per sample).
        val table = dir.resolve("still.csv")
        val rnd = java.util.Random(11)
        val f = 100.0
        Files.newBufferedWriter(table).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az\n")
            for (k in 0 until 12_000) {
                fun g(n: Double) = n * Math.sqrt(f) * rnd.nextGaussian()
                w.write("${k / f},${g(0.001)},${g(0.001)},${g(0.001)},${g(0.02)},${g(0.02)},${9.81 + g(0.02)}\n")
            }
        }
        val out = dir.resolve("configs")
        val r = fusion("allan", table.toString(), "--configs", out.toString(), "--quiet")
        assertEquals(ExitCode.OK, r.code, r.err)
        val model = NoiseModel.parse(r.out, "imu.yaml")
        assertEquals(r.out, Files.readString(out.resolve("imu.yaml")))
        assertEquals(0.001, model.gyroscopeNoiseDensity, 0.0002)
        val rate = model.rateHz!!
        assertEquals(f, rate, 1e-6)
        // The discrete figures at the rate, stated beside the continuous ones.
        val sd = Regex("""# gyroscope discrete at 100 Hz: white noise sigma_d ([^ ]+) rad/s, bias random walk sigma_bd ([^ ]+) rad/s per sample""").find(r.out)
        assertTrue(sd != null, r.out)
        assertEquals(model.gyroscopeNoiseDensity * 10, sd!!.groupValues[1].toDouble(), 1e-5 * model.gyroscopeNoiseDensity * 10)
        assertEquals(model.gyroscopeRandomWalk / 10, sd.groupValues[2].toDouble(), 1e-5 * model.gyroscopeRandomWalk / 10)
        val read = python("configs", out, "cv2, yaml").mapValues { (_, v) -> v }
        fun value(file: String, key: String) = read.getValue(file).single { it[0] == key }[1].toDouble()
        fun close(expected: Double, actual: Double, what: String) = assertEquals(expected, actual, 1e-5 * expected, what)
        // kalibr and OpenVINS: continuous time, as they are.
        val figures = mapOf(
            "gyroscope_noise_density" to model.gyroscopeNoiseDensity, "gyroscope_random_walk" to model.gyroscopeRandomWalk,
            "accelerometer_noise_density" to model.accelerometerNoiseDensity, "accelerometer_random_walk" to model.accelerometerRandomWalk,
        )
        assertEquals(NoiseModel.KEYS.toSet(), figures.keys)
        for ((k, v) in figures) {
            close(v, value("kalibr", k), "kalibr $k")
            close(v, value("kalibr_imu_chain.yaml", k), "OpenVINS $k")
        }
        close(rate, value("kalibr_imu_chain.yaml", "update_rate"), "OpenVINS update_rate")
        assertEquals("kalibr", read.getValue("kalibr_imu_chain.yaml").single { it[0] == "model" }[1])
        assertEquals(listOf(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0),
            read.getValue("kalibr_imu_chain.yaml").single { it[0] == "T_i_b" }.drop(1).map { it.toDouble() })
        // VINS: per sample at the rate: noise × √f, bias walk × √f (its bias moves by acc_w·dt per sample).
        val sf = Math.sqrt(rate)
        close(model.accelerometerNoiseDensity * sf, value("vins_imu.yaml", "acc_n"), "acc_n")
        close(model.gyroscopeNoiseDensity * sf, value("vins_imu.yaml", "gyr_n"), "gyr_n")
        close(model.accelerometerRandomWalk * sf, value("vins_imu.yaml", "acc_w"), "acc_w")
        close(model.gyroscopeRandomWalk * sf, value("vins_imu.yaml", "gyr_w"), "gyr_w")
        // ORB-SLAM3: continuous, with the rate it discretises them at.
        close(model.gyroscopeNoiseDensity, value("orbslam3_imu.yaml", "IMU.NoiseGyro"), "IMU.NoiseGyro")
        close(model.accelerometerNoiseDensity, value("orbslam3_imu.yaml", "IMU.NoiseAcc"), "IMU.NoiseAcc")
        close(model.gyroscopeRandomWalk, value("orbslam3_imu.yaml", "IMU.GyroWalk"), "IMU.GyroWalk")
        close(model.accelerometerRandomWalk, value("orbslam3_imu.yaml", "IMU.AccWalk"), "IMU.AccWalk")
        close(rate, value("orbslam3_imu.yaml", "IMU.Frequency"), "IMU.Frequency")
        println("noise configurations via cv2.FileStorage and PyYAML: N_g ${model.gyroscopeNoiseDensity} rad/s/sqrt(Hz) → gyr_n ${value("vins_imu.yaml", "gyr_n")} rad/s at $rate Hz; " +
            "N_a ${model.accelerometerNoiseDensity} → acc_n ${value("vins_imu.yaml", "acc_n")}")
    }

    /** `fusion replay` of [input] with [options]: its rows (t_s, q and the rest as text). */
    private fun replayRows(input: Path, vararg options: String): List<List<String>> {
        val out = Files.createTempFile(dir, "replay", ".csv")
        val r = fusion("replay", input.toString(), "-o", out.toString(), "--quiet", *options)
        assertEquals(ExitCode.OK, r.code, r.err)
        return csv(out)
    }

    /**
     * Rows of the replay of an export against those of the original: the same count and every
     * quaternion component within [tolerance]; t_s counts from the first row in an export (its
     * own clock), so the times are compared as differences from the first. Returns the largest
     * quaternion difference.
     */
    private fun sameReplay(original: List<List<String>>, exported: List<List<String>>, tolerance: Double, what: String): Double {
        assertEquals(original.size, exported.size, "$what rows")
        var worst = 0.0
        val t0 = original[0][0].toDouble()
        val e0 = exported[0][0].toDouble()
        for (k in original.indices) {
            assertEquals(original[k][0].toDouble() - t0, exported[k][0].toDouble() - e0, 1e-9, "$what row $k time")
            for (c in 1..4) {
                val d = Math.abs(original[k][c].toDouble() - exported[k][c].toDouble())
                if (!(d <= tolerance) && !(original[k][c] == "NaN" && exported[k][c] == "NaN")) {
                    throw AssertionError("$what row $k q${c - 1}: ${original[k][c]} against ${exported[k][c]}")
                }
                if (d.isFinite()) worst = maxOf(worst, d)
            }
        }
        return worst
    }

    @Test
    fun `an export replays as the original did, EuRoC 9D with its magnetometer and Kalibr 6D`() {
        // The replay of the export steps on the same samples at the same times, so the orientation is the
        // same within float precision: a session's readings are floats read as their exact double, the
        // export's their shortest decimal read as a double (a difference in the ninth digit).
        val original = replayRows(session, "--default-settings")
        val euroc = dir.resolve("roundtrip-euroc")
        assertEquals(ExitCode.OK, fusion("export", session.toString(), "--format", "euroc", "-o", euroc.toString(), "--quiet").code)
        val r = fusion("replay", euroc.toString(), "-o", dir.resolve("euroc-replay.csv").toString(), "--default-settings")
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue("EuRoC (ASL) IMU data roundtrip-euroc: " in r.err && "600 gyroscope, 600 accelerometer, 600 magnetometer" in r.err, r.err)
        val eurocWorst = sameReplay(original, csv(dir.resolve("euroc-replay.csv")), 1e-6, "euroc")
        // The mav0 folder and its imu0/data.csv alone read the same (the latter without the magnetometer).
        assertEquals(csv(dir.resolve("euroc-replay.csv")), replayRows(euroc.resolve("mav0"), "--default-settings"))
        val sixD = replayRows(session, "--default-settings", "--mode", "6d")
        sameReplay(sixD, replayRows(euroc.resolve("mav0/imu0/data.csv"), "--default-settings", "--mode", "6d"), 1e-6, "euroc imu0 alone")
        val kalibr = dir.resolve("roundtrip-kalibr")
        assertEquals(ExitCode.OK, fusion("export", session.toString(), "--format", "kalibr", "-o", kalibr.toString(), "--quiet").code)
        val kalibrWorst = sameReplay(sixD, replayRows(kalibr, "--default-settings", "--mode", "6d"), 1e-6, "kalibr")
        assertEquals(replayRows(kalibr, "--default-settings", "--mode", "6d"), replayRows(kalibr.resolve("imu0.csv"), "--default-settings", "--mode", "6d"))
        println("round trip: euroc 9D ${original.size} rows, largest quaternion difference $eurocWorst; kalibr 6D ${sixD.size} rows, $kalibrWorst")
    }

    @Test
    fun `real exports replay the same after an EuRoC export, within the float rounding of the readings`() {
        val root = Paths.get("../shared/data/realdata").let { if (Files.isDirectory(it)) it else Paths.get("../../shared/data/realdata") }
        assumeTrue(Files.isDirectory(root), "no ../shared/data/realdata beside the repository: real exports not tested")
        fun roundTrip(name: String, input: Path, mode: String, tolerance: Double): Double {
            val out = dir.resolve("$name-euroc")
            val e = fusion("export", input.toString(), "--format", "euroc", "-o", out.toString(), "--default-settings", "--mode", mode)
            assertEquals(ExitCode.OK, e.code, e.err)
            val original = replayRows(input, "--default-settings", "--mode", mode)
            val exported = replayRows(out, "--default-settings", "--mode", mode)
            // Rows before the first accelerometer reading are not exported.
            val skipped = original.size - exported.size
            assertTrue(skipped in 0..2, "$name: $skipped rows")
            val worst = sameReplay(original.drop(skipped), exported, tolerance, "$name → euroc")
            println("$name → euroc → replay ($mode): ${exported.size} rows ($skipped before the first accelerometer reading not exported); largest quaternion difference $worst")
            return worst
        }
        // Sensor Logger with every sensor at the same instants: only the readings' rounding to float differs
        // (its readings are doubles); measured: the largest difference is at the second row (3.4e-4), about
        // 1e-6 by row 7000.
        val sl = roundTrip("sl-unknown-shuhrat", root.resolve("sl-unknown-shuhrat"), "9d", 1e-3)
        // phyphox (iOS) with the accelerometer at its own times: a gyroscope step holds the latest reading
        // either way, but the filter also sees the readings between two gyroscope samples in the original.
        val pp = roundTrip("pp-ios-foger3", root.resolve("pp-ios-foger3/dataset/raw/Falling exp 2023-06-09 12-54-45-round1-nicole"), "6d", 1e-3)
        assertTrue(sl > 0.0 && pp > 0.0) // the readings were rounded: a difference of exactly 0 would mean the export was not read
    }

    @Test
    fun `heading tare on replay and export turns the output frame about up only`() {
        val plain = replayRows(session, "--default-settings")
        fun angle(a: String, b: String) = Math.abs(Math.IEEEremainder(a.toDouble() - b.toDouble(), 360.0))
        fun checkTare(rows: List<List<String>>, deltaDeg: Double, what: String) {
            assertEquals(plain.size, rows.size)
            for ((k, r) in rows.withIndex()) {
                if (plain[k][1] == "NaN") { assertEquals("NaN", r[1]); continue }
                assertEquals(0.0, angle(plain[k][8], (r[8].toDouble() - deltaDeg).toString()), 2e-4, "$what row $k yaw + Δ")
                assertEquals(plain[k][9], r[9], "$what row $k pitch")
                assertEquals(0.0, angle(plain[k][10], r[10]), 2e-4, "$what row $k roll")
                assertEquals(plain[k][13].toDouble(), r[13].toDouble(), 2e-5, "$what row $k vertical linear acceleration")
            }
        }
        // At a time: the first row with an orientation at or after it reads the heading given.
        val at = replayRows(session, "--default-settings", "--heading-tare", "2.5=30")
        val k = at.indexOfFirst { it[0].toDouble() >= 2.5 }
        assertEquals(30.0, at[k][8].toDouble(), 1e-4)
        checkTare(at, at[k][8].toDouble() - plain[k][8].toDouble(), "tare at 2.5 s")
        // At the start: the first orientation reads 0.
        val start = replayRows(session, "--default-settings", "--heading-tare", "start")
        val first = start.indexOfFirst { it[1] != "NaN" }
        assertEquals(0.0, Math.abs(start[first][8].toDouble()), 1e-4)
        checkTare(start, -plain[first][8].toDouble(), "tare at start")
        checkTare(replayRows(session, "--default-settings", "--heading-offset", "90"), 90.0, "offset 90")
        // The export carries the tared orientation and names its frame.
        val out = dir.resolve("tared-euroc")
        val r = fusion("export", session.toString(), "--format", "euroc", "-o", out.toString(), "--default-settings", "--heading-tare", "2.5=30")
        assertEquals(ExitCode.OK, r.code, r.err)
        val pose = csv(out.resolve("mav0/state_groundtruth_estimate0/data.csv"))
        for (j in pose.indices) for (c in 0 until 4) assertEquals(at[j][1 + c].toDouble(), pose[j][4 + c].trim().toDouble(), 1e-9, "pose $j q$c")
        val yaml = Files.readString(out.resolve("mav0/state_groundtruth_estimate0/sensor.yaml"))
        assertTrue("R is ENU turned about up (heading tare: every heading + " in yaml && "so that it reads 30 deg at t = 2.5 s" in yaml, yaml)
        // Usage and data errors.
        assertEquals(ExitCode.USAGE, fusion("replay", session.toString(), "--heading-tare", "start", "--heading-offset", "3").code)
        assertEquals(ExitCode.USAGE, fusion("replay", session.toString(), "--heading-tare", "soon").code)
        val late = fusion("replay", session.toString(), "--heading-tare", "60", "-o", dir.resolve("late.csv").toString())
        assertEquals(ExitCode.DATA_ERROR, late.code, late.err)
        assertTrue("no orientation at or after t = 60 s" in late.err, late.err)
        assertTrue(!Files.exists(dir.resolve("late.csv")))
    }

    @Test
    fun `an iOS and an Android Sensor Logger export of the same motion export to the same frame`() {
        // The session's samples written as both apps write them: Android's convention, and raw iOS
        // (CoreMotion's: the acceleration with the opposite sign); gyroscope and magnetometer alike.
        fun table(name: String) = csv(session.resolve(name)).map { r -> r[0] to r.subList(1, 4).map { it.toDouble() } }
        val streams = mapOf("TotalAcceleration.csv" to table("accelerometer.csv"), "Gyroscope.csv" to table("gyroscope.csv"), "Magnetometer.csv" to table("magnetometer.csv"))
        val t0 = times.first()
        val exported = HashMap<String, List<String>>()
        for (platform in listOf("android", "ios")) {
            val folder = Files.createDirectories(dir.resolve("sensor-logger-$platform"))
            Files.writeString(folder.resolve("Metadata.csv"), "version,device name,platform,appVersion,standardisation\n3,phone,$platform,1.40.0,false\n")
            for ((file, rows) in streams) {
                val sign = if (platform == "ios" && file == "TotalAcceleration.csv") -1.0 else 1.0
                Files.write(folder.resolve(file), listOf("time,seconds_elapsed,z,y,x") + rows.map { (t, v) ->
                    "$t,${(t.toLong() - t0) / 1e9},${sign * v[2]},${sign * v[1]},${sign * v[0]}"
                })
            }
            val out = dir.resolve("sensor-logger-$platform-euroc")
            val r = fusion("export", folder.toString(), "--format", "euroc", "-o", out.toString(), "--default-settings")
            assertEquals(ExitCode.OK, r.code, r.err)
            val meta = Files.readString(out.resolve("mav0/imu0/sensor.yaml"))
            assertTrue("Readings in Android device axes: x right, y up (top edge), z out of the screen; right-handed" in meta, meta)
            exported[platform] = listOf("imu0", "mag0", "state_groundtruth_estimate0").flatMap { Files.readAllLines(out.resolve("mav0/$it/data.csv")) }
        }
        assertEquals(exported.getValue("android"), exported.getValue("ios"))
        // The session names its frames in meta.json, and every reader of it still opens it (this test's replays).
        val meta = Files.readString(session.resolve("meta.json"))
        assertTrue(Regex(""""frames":\s*\{\s*"device":\s*"android_sensor: x right, y up, z out of screen",\s*"world":\s*"ENU: x east, y magnetic north, z up",\s*"quaternion":\s*"qw,qx,qy,qz Hamilton, device to world"""").containsMatchIn(meta), meta)
        // And that frame is the session's: +9.8 m/s² on the up axis at rest, the same rows as the session's own export.
        val own = dir.resolve("session-euroc-frames")
        assertEquals(ExitCode.OK, fusion("export", session.toString(), "--format", "euroc", "-o", own.toString(), "--default-settings", "--quiet").code)
        val ownImu = Files.readAllLines(own.resolve("mav0/imu0/data.csv"))
        assertEquals(ownImu, exported.getValue("android").take(ownImu.size))
        println("sensor logger android and ios (raw CoreMotion signs) → euroc: ${exported.getValue("ios").size} lines, identical, and equal to the session's own IMU rows")
    }

    @Test
    fun `refused outputs create nothing`() {
        val out = dir.resolve("inside")
        val r = fusion("export", session.toString(), "--format", "euroc", "-o", session.resolve("x").toString())
        assertEquals(ExitCode.USAGE, r.code)
        assertTrue("lies inside the input" in r.err, r.err)
        assertTrue(!Files.exists(session.resolve("x")))
        val f = fusion("export", session.toString(), "--format", "ros9", "-o", out.toString())
        assertEquals(ExitCode.USAGE, f.code)
        assertTrue("--format expects euroc, kalibr, gcsv or ros2, got 'ros9'" in f.err, f.err)
        // Options with nothing to act on are refused, not ignored: kalibr and gcsv hold no orientation, gcsv no noise.
        for ((args, message) in listOf(
            listOf("--format", "kalibr", "--offline", "--beta", "0.5") to "--beta, --offline: a kalibr export holds no orientation",
            listOf("--format", "gcsv", "--heading-offset", "45") to "--heading-offset: a gcsv export holds no orientation",
            listOf("--format", "gcsv", "--noise", dir.resolve("any.yaml").toString()) to "--noise: a gcsv export has no place for a noise model",
        )) {
            val u = fusion("export", session.toString(), *args.toTypedArray(), "-o", out.toString())
            assertEquals(ExitCode.USAGE, u.code, u.err)
            assertTrue(message in u.err, u.err)
        }
        // A file format's OUT that names a folder or a compressed file.
        for ((format, name, message) in listOf(
            Triple("gcsv", "x.gcsv.gz", "ends in .gz, but a gcsv export is written plain"),
            Triple("ros2", "rosdir/", "ends in '/', but a ros2 export is one file"),
        )) {
            val u = fusion("export", session.toString(), "--format", format, "-o", dir.resolve("plain").toString() + "/" + name)
            assertEquals(ExitCode.USAGE, u.code, u.err)
            assertTrue(message in u.err, u.err)
        }
        val bad = dir.resolve("bad-noise.yaml")
        Files.writeString(bad, "gyroscope_noise_density: 1e-4\ngyroscope_random_walk: lots\n")
        val n = fusion("export", session.toString(), "--format", "kalibr", "--noise", bad.toString(), "-o", out.toString())
        assertEquals(ExitCode.DATA_ERROR, n.code)
        assertTrue("bad-noise.yaml:2:" in n.err && "gyroscope_random_walk: 'lots'" in n.err, n.err)
        assertTrue(!Files.exists(out))
        assertTrue(Files.list(dir).use { s -> s.noneMatch { it.fileName.toString().startsWith(".inside") } })
    }

    @Test
    fun `a clock that starts at 0 keeps ten digits for kalibr, and a pause leaves the rates alone`() {
        // A table from t = 0 at 100 Hz, paused for 60 s after 3 s (every sensor silent), then 3 s more.
        val table = dir.resolve("paused.csv")
        val lines = mutableListOf("t_s,gx,gy,gz,ax,ay,az,mx,my,mz")
        for (k in 0 until 600) {
            val t = k * 0.01 + if (k >= 300) 60.0 else 0.0
            lines += String.format(java.util.Locale.ROOT, "%.2f,0.01,0,0,0,0,9.81,20,0,-40", t)
        }
        Files.write(table, lines)
        val out = dir.resolve("paused-kalibr")
        val r = fusion("export", table.toString(), "--format", "kalibr", "-o", out.toString(), "--quiet")
        assertEquals(ExitCode.OK, r.code, r.err)
        val stamps = Files.readAllLines(out.resolve("imu0.csv")).drop(1).map { it.substringBefore(',') }
        assertEquals("0000000000", stamps[0], "the first time, padded")
        for ((k, s) in stamps.withIndex()) {
            assertTrue(s.length >= 10, "row $k: '$s' has fewer than ten digits")
            // kalibr_bagcreater's split: seconds from all but the last nine digits.
            val ns = s.substring(0, s.length - 9).toLong() * 1_000_000_000L + s.substring(s.length - 9).toLong()
            assertEquals(Math.round((k * 0.01 + if (k >= 300) 60.0 else 0.0) * 1e9), ns, "row $k")
        }
        val yaml = Files.readAllLines(out.resolve("imu.yaml")).single { it.startsWith("update_rate:") }
        assertTrue(yaml.startsWith("update_rate: 100.000"), "the pause is no part of the rate: $yaml")
        val euroc = dir.resolve("paused-euroc")
        assertEquals(ExitCode.OK, fusion("export", table.toString(), "--format", "euroc", "-o", euroc.toString(), "--quiet").code)
        val sensor = Files.readAllLines(euroc.resolve("mav0/imu0/sensor.yaml")).single { it.startsWith("rate_hz:") }
        assertTrue(sensor.startsWith("rate_hz: 100.000"), sensor)
    }

    @Test
    fun `a clock that starts before 0 is moved a whole second later in every format, and says so`() {
        // As a phyphox export whose first samples come before its t = 0: 100 Hz from t = -0.0758 s.
        val table = dir.resolve("early.csv")
        val lines = mutableListOf("t_s,gx,gy,gz,ax,ay,az,mx,my,mz")
        for (k in 0 until 300) lines += String.format(java.util.Locale.ROOT, "%.4f,0.01,0,0,0,0,9.81,20,0,-40", -0.0758 + k * 0.01)
        Files.write(table, lines)
        fun expected(k: Int) = Math.round((-0.0758 + k * 0.01) * 1e9) + 1_000_000_000L
        val kalibr = dir.resolve("early-kalibr")
        val r = fusion("export", table.toString(), "--format", "kalibr", "-o", kalibr.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue("early.csv starts before t = 0; every time written is 1 s later" in r.err, r.err)
        val stamps = Files.readAllLines(kalibr.resolve("imu0.csv")).drop(1).map { it.substringBefore(',') }
        assertEquals(300, stamps.size)
        for ((k, s) in stamps.withIndex()) {
            assertTrue(s.length >= 10 && s.all { it.isDigit() }, "row $k: '$s'")
            assertEquals(expected(k), s.toLong(), "row $k")
        }
        assertTrue("the recording's own clock + 1 s (it starts before 0)" in Files.readString(kalibr.resolve("imu.yaml")))
        val euroc = dir.resolve("early-euroc")
        assertEquals(ExitCode.OK, fusion("export", table.toString(), "--format", "euroc", "-o", euroc.toString(), "--quiet").code)
        for (file in listOf("imu0", "mag0")) {
            val times = Files.readAllLines(euroc.resolve("mav0/$file/data.csv")).drop(1).map { it.substringBefore(',').toLong() }
            assertEquals(expected(0), times.first(), file)
            assertEquals(expected(299), times.last(), file)
        }
        assertTrue("+ 1 s" in Files.readString(euroc.resolve("mav0/mag0/sensor.yaml")))
        // A time before 0 wraps round in MCAP's unsigned log time: none may be written.
        val mcap = dir.resolve("early.mcap")
        assertEquals(ExitCode.OK, fusion("export", table.toString(), "--format", "ros2", "-o", mcap.toString(), "--quiet").code)
        val read = python("ros2", mcap, "mcap_ros2.decoder, rosbags.highlevel, yaml")
        assertEquals(expected(0), read.getValue("mcap:/imu/data_raw").first()[0].toLong())
        assertEquals(expected(0), read.getValue("mcap:/imu/mag").first()[0].toLong())
    }

    @Test
    fun `a step back to before the first event is refused by the export, not written negative`() {
        // From t = 0.3 s to 0.59 s, then back to -0.05 s (a step back under a second, which the replay passes over).
        val table = dir.resolve("back.csv")
        val lines = mutableListOf("t_s,gx,gy,gz,ax,ay,az,mx,my,mz")
        for (k in 0 until 30) lines += String.format(java.util.Locale.ROOT, "%.4f,0.01,0,0,0,0,9.81,20,0,-40", 0.3 + k * 0.01)
        for (k in 0 until 100) lines += String.format(java.util.Locale.ROOT, "%.4f,0.01,0,0,0,0,9.81,20,0,-40", -0.05 + k * 0.01)
        Files.write(table, lines)
        for (format in listOf("kalibr", "ros2")) {
            val out = dir.resolve("back-$format" + if (format == "ros2") ".mcap" else "")
            val r = fusion("export", table.toString(), "--format", format, "-o", out.toString())
            assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
            assertTrue("before the recording's first event (a step back in time)" in r.err, r.err)
            assertTrue(!Files.exists(out), "nothing left at $out")
        }
    }

    @Test
    fun `a recording without a magnetometer is replayed and exported in 6D, and says so`() {
        val table = dir.resolve("no-mag.csv")
        val lines = mutableListOf("t_s,gx,gy,gz,ax,ay,az")
        for (k in 0 until 300) lines += String.format(java.util.Locale.ROOT, "%.2f,0.01,0,0,0,0,9.81", k * 0.01)
        Files.write(table, lines)
        val replay = fusion("replay", table.toString(), "-o", dir.resolve("no-mag-replay.csv").toString())
        assertEquals(ExitCode.OK, replay.code, replay.err)
        assertTrue("no magnetometer: 6D" in replay.err, replay.err)
        // No half second waiting for a field: every row from the first has an orientation.
        val rows = csv(dir.resolve("no-mag-replay.csv"))
        assertEquals(300, rows.size)
        assertTrue(rows.all { it[1] != "NaN" && it[1].isNotEmpty() }, "rows without an orientation: ${rows.count { it[1] == "NaN" || it[1].isEmpty() }}")
        val out = dir.resolve("no-mag-euroc")
        val r = fusion("export", table.toString(), "--format", "euroc", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val yaml = Files.readString(out.resolve("mav0/state_groundtruth_estimate0/sensor.yaml"))
        assertTrue("Madgwick 6D" in yaml && "unknown heading" in yaml && "magnetic north" !in yaml, yaml)
        // --quiet keeps the note off; --mode 9d is still the user's to ask for.
        assertFalse("6D" in fusion("replay", table.toString(), "-o", dir.resolve("q.csv").toString(), "--quiet").err)
    }

    @Test
    fun `an imu table exports like a session`() {
        val table = dir.resolve("table.csv")
        assertEquals(ExitCode.OK, fusion("simulate", "-o", table.toString(), "--duration", "5").code)
        val out = dir.resolve("table-euroc")
        val r = fusion("export", table.toString(), "--format", "euroc", "-o", out.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertEquals(501, Files.readAllLines(out.resolve("mav0/imu0/data.csv")).size)
        assertTrue(Files.exists(out.resolve("mav0/mag0/data.csv")))
    }

    /** Runs read_export.py [mode] on [path]; skips when python3 or [module] is missing. */
    private fun python(mode: String, path: Path, module: String): Map<String, List<List<String>>> {
        val python = System.getenv("FUSION_PYTHON") ?: "python3"
        val probe = runCatching { run(listOf(python, "-c", "import $module"), dir, 120) }.getOrNull()
        assumeTrue(probe != null && probe.first == 0) {
            "skipped: $python cannot import $module (pip install evo pyyaml mcap mcap-ros2-support rosbags opencv-python-headless; .ci/run installs them where pip reaches PyPI)"
        }
        val script = dir.resolve("read_export.py")
        javaClass.getResourceAsStream("export/read_export.py")!!.use { Files.copy(it, script, java.nio.file.StandardCopyOption.REPLACE_EXISTING) }
        val p = run(listOf(python, script.toString(), mode, path.toString()), dir, 300)
        assertEquals(0, p.first, p.third)
        return parse(p.second)
    }

    /** Builds the gcsv reader (telemetry-parser from crates.io) once under target/; skips without cargo or crates.io. */
    private fun gcsvReader(): Path {
        val cargo = System.getenv("CARGO") ?: "cargo"
        val version = runCatching { run(listOf(cargo, "--version"), dir, 60) }.getOrNull()
        assumeTrue(version != null && version.first == 0) { "skipped: cargo not found (install Rust to check gcsv with Gyroflow's telemetry-parser)" }
        val project = Paths.get("target", "gcsv-reader").toAbsolutePath()
        Files.createDirectories(project.resolve("src"))
        for (f in listOf("Cargo.toml", "src/main.rs")) {
            val bytes = javaClass.getResourceAsStream("export/gcsv-reader/$f")!!.use { it.readBytes() }
            val target = project.resolve(f)
            if (!Files.exists(target) || !Files.readAllBytes(target).contentEquals(bytes)) Files.write(target, bytes)
        }
        val build = run(listOf(cargo, "build", "-q"), project, 900)
        assumeTrue(build.first == 0) { "skipped: building telemetry-parser failed (offline?): ${build.third.lines().takeLast(5).joinToString(" | ")}" }
        return project.resolve("target/debug/gcsv-reader")
    }

    private companion object {
        fun csv(p: Path): List<List<String>> = Files.readAllLines(p).drop(1).filter { it.isNotBlank() }.map { it.split(',') }

        /** "key v1 v2 …" lines grouped by key. */
        fun parse(text: String): Map<String, List<List<String>>> =
            text.lines().filter { it.isNotBlank() }.map { it.split(' ') }.groupBy({ it[0] }, { it.drop(1) })

        /** Exit code, standard output, standard error; a process over [seconds] is killed and fails. */
        fun run(command: List<String>, dir: Path, seconds: Long): Triple<Int, String, String> {
            val err = Files.createTempFile(dir, "err", ".txt")
            val out = Files.createTempFile(dir, "out", ".txt")
            val p = ProcessBuilder(command).directory(dir.toFile()).redirectOutput(out.toFile()).redirectError(err.toFile()).start()
            if (!p.waitFor(seconds, TimeUnit.SECONDS)) {
                p.destroyForcibly()
                return Triple(-1, "", "timed out after $seconds s: ${command.joinToString(" ")}")
            }
            return Triple(p.exitValue(), Files.readString(out), Files.readString(err)).also { Files.delete(out); Files.delete(err) }
        }
    }
}
