package dev.motionfusion.cli

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionCalibration
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path

/** `fusion calibrate`, `fusion allan` and `fusion replay --calibration` on simulated sessions. */
class CalibrationCommandsTest {
    @TempDir
    lateinit var dir: Path

    private val hardIron = Vector3(35.0, -20.0, 60.0)
    private val gyroBias = Vector3(0.01, -0.02, 0.015)

    /** A session with uncalibrated streams: still, turning through all orientations, still again. */
    private fun session(name: String, s: SimulationSettings, uncalibrated: Boolean = true, meta: SessionMetadata = SessionMetadata()): Path {
        val d = dir.resolve(name)
        SessionWriter.create(d, meta.copy(source = "test", startAnchor = ClockAnchor(0L, 1_000_000_000L))).use { w ->
            MotionSimulator(s).forEach {
                val t = 1_000_000_000L + it.timestampNs
                w.accelerometer(t, it.acc.x.toFloat(), it.acc.y.toFloat(), it.acc.z.toFloat(), 3)
                if (uncalibrated) {
                    w.magnetometerUncalibrated(t, it.mag.x.toFloat(), it.mag.y.toFloat(), it.mag.z.toFloat(), 0f, 0f, 0f, 3)
                    w.gyroscopeUncalibrated(t, it.gyro.x.toFloat(), it.gyro.y.toFloat(), it.gyro.z.toFloat(), 0f, 0f, 0f, 3)
                }
                w.magnetometer(t, (it.mag.x - hardIron.x).toFloat(), (it.mag.y - hardIron.y).toFloat(), (it.mag.z - hardIron.z).toFloat(), 3)
                w.gyroscope(t, it.gyro.x.toFloat(), it.gyro.y.toFloat(), it.gyro.z.toFloat(), 3)
            }
        }
        return d
    }

    private val turning = SimulationSettings(
        seed = 4, rateHz = 100.0, durationS = 90.0, angularRate = 3.0,
        restWindows = listOf(TimeWindow(0.0, 10.0), TimeWindow(80.0, 91.0)),
        gyroBias = gyroBias, gyroNoise = 0.003,
        hardIron = hardIron, hardIronWindow = TimeWindow(0.0, 91.0), magSoftIron = Matrix3.symmetric(1.1, 0.92, 1.0, 0.05, 0.0, -0.03),
    )

    @Test
    fun `calibrate writes the fits as JSON and replay applies them`() {
        val s = session("turning", turning)
        val r = fusion("calibrate", s.toString(), "-o", dir.resolve("cal.json").toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue("magnetometer (magnetometer_uncalibrated, full)" in r.err, r.err)
        assertTrue("accelerometer: not calibrated: 2 distinct still poses" in r.err, r.err)
        val cal = CalibrationJson.parse(Files.readString(dir.resolve("cal.json")), "cal.json")
        assertTrue((cal.magnetometer!!.correction.offset - hardIron).norm() < 1.0, "${cal.magnetometer}")
        assertTrue((cal.gyroscope!!.bias - gyroBias).norm() < 3e-4, "${cal.gyroscope}")
        assertEquals(SessionStream.GYROSCOPE_UNCALIBRATED, cal.gyroscope!!.stream)
        // The same JSON on standard output.
        assertEquals(Files.readString(dir.resolve("cal.json")), fusion("calibrate", s.toString(), "--quiet").out)

        val plain = fusion("replay", s.toString(), "--quiet").out
        val calibrated = fusion("replay", s.toString(), "--quiet", "--calibration", dir.resolve("cal.json").toString())
        assertEquals(ExitCode.OK, calibrated.code, calibrated.err)
        assertEquals(plain.lines().size, calibrated.out.lines().size)
        assertTrue(plain != calibrated.out)
    }

    @Test
    fun `replay applies the calibration of meta_json by default only when the live filter used it`() {
        val s = session("turning", turning)
        assertEquals(ExitCode.OK, fusion("calibrate", s.toString(), "-o", dir.resolve("cal.json").toString(), "--quiet").code)
        val cal = CalibrationJson.parse(Files.readString(dir.resolve("cal.json")), "cal.json")
        val plain = fusion("replay", s.toString(), "--quiet").out
        val withFile = fusion("replay", s.toString(), "--quiet", "--calibration", dir.resolve("cal.json").toString()).out

        val live = session("applied", turning, meta = SessionMetadata(calibration = SessionCalibration(cal, appliedInLiveFilter = true)))
        val r = fusion("replay", live.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertEquals(withFile, r.out)
        assertTrue("applying the calibration the live filter used" in r.err, r.err)
        assertEquals(plain, fusion("replay", live.toString(), "--quiet", "--calibration", "none").out)

        val stored = session("stored", turning, meta = SessionMetadata(calibration = SessionCalibration(cal, appliedInLiveFilter = false)))
        assertEquals(plain, fusion("replay", stored.toString(), "--quiet").out)
        assertEquals(withFile, fusion("replay", stored.toString(), "--quiet", "--calibration", "recorded").out)

        val none = fusion("replay", s.toString(), "--calibration", "recorded")
        assertEquals(ExitCode.USAGE, none.code)
        assertTrue("has no calibration in its meta.json" in none.err, none.err)
    }

    @Test
    fun `a calibration for streams the recording lacks, and a broken file, are data errors`() {
        val s = session("turning", turning)
        assertEquals(ExitCode.OK, fusion("calibrate", s.toString(), "-o", dir.resolve("cal.json").toString(), "--quiet").code)
        val other = session("plain", turning.copy(durationS = 12.0, restWindows = emptyList()), uncalibrated = false)
        val r = fusion("replay", other.toString(), "--calibration", dir.resolve("cal.json").toString(), "-o", dir.resolve("out.csv").toString())
        assertEquals(ExitCode.DATA_ERROR, r.code)
        assertTrue("cal.json: applies to magnetometer_uncalibrated, gyroscope_uncalibrated, which plain does not have" in r.err, r.err)
        assertTrue(!Files.exists(dir.resolve("out.csv")), "no output for a refused run")
        val badJson = "{\"format\": \"motion-fusion-calibration\", \"format_version\": 1, \"gyroscope\": {\"stream\": \"gyroscope\", \"bias_rad_s\": [1, 2]}}"
        Files.writeString(dir.resolve("bad.json"), badJson)
        val bad = fusion("replay", s.toString(), "--calibration", dir.resolve("bad.json").toString())
        assertEquals(ExitCode.DATA_ERROR, bad.code)
        assertTrue("bad.json:1:${badJson.indexOf("[1, 2]") + 1}: gyroscope.bias_rad_s: expected 3 numbers, got 2" in bad.err, bad.err)
        assertEquals(ExitCode.IO_ERROR, fusion("replay", s.toString(), "--calibration", dir.resolve("none.json").toString()).code)
    }

    @Test
    fun `a recording that turns too little is refused and nothing is written`() {
        val s = session("flat", turning.copy(angularRate = 0.05, restWindows = emptyList(), durationS = 20.0))
        val r = fusion("calibrate", s.toString(), "-o", dir.resolve("cal.json").toString())
        assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
        assertTrue("magnetometer: not calibrated: the readings cover too few directions" in r.err, r.err)
        assertTrue("nothing could be calibrated" in r.err, r.err)
        assertTrue(!Files.exists(dir.resolve("cal.json")))
    }

    @Test
    fun `allan writes kalibr YAML and an SVG plot`() {
        val still = SimulationSettings(
            seed = 5, rateHz = 100.0, durationS = 600.0, angularRate = 0.0, gyroNoise = 0.0, accNoise = 0.0,
            gyroNoiseDensity = 0.002, accNoiseDensity = 0.02, gyroBiasDrift = 1e-4, accBiasDrift = 1e-3,
        )
        val s = session("still", still)
        val yaml = dir.resolve("imu.yaml")
        val svg = dir.resolve("allan.svg")
        val r = fusion("allan", s.toString(), "-o", yaml.toString(), "--plot", svg.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val values = Files.readAllLines(yaml).filter { !it.startsWith("#") && ':' in it }
            .associate { it.substringBefore(':').trim() to it.substringAfter(':').substringBefore('#').trim() }
        assertEquals(setOf("accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density", "gyroscope_random_walk", "rostopic", "update_rate"), values.keys)
        assertEquals(0.002, values["gyroscope_noise_density"]!!.toDouble(), 0.0003)
        assertEquals(0.02, values["accelerometer_noise_density"]!!.toDouble(), 0.003)
        assertEquals(100.0, values["update_rate"]!!.toDouble(), 0.01)
        assertTrue("gyroscope: 60000 samples at 100 Hz" in r.err, r.err)
        val plot = Files.readString(svg)
        assertTrue(plot.startsWith("<svg") && "gyroscope Allan deviation" in plot && "stroke-dasharray" in plot)
        assertEquals(ExitCode.USAGE, fusion("allan", s.toString(), "-o", yaml.toString(), "--plot", yaml.toString()).code)
        assertEquals(ExitCode.USAGE, fusion("allan").code)
        assertEquals(ExitCode.USAGE, fusion("allan", s.toString(), "--bogus").code)
    }

    @Test
    fun `help and usage errors`() {
        for (c in listOf("calibrate", "allan")) {
            val h = fusion(c, "--help")
            assertEquals(ExitCode.OK, h.code)
            assertTrue(h.out.startsWith("Usage: fusion $c"), h.out)
            assertTrue(c in fusion("--help").out)
        }
        assertTrue("--calibration FILE" in fusion("replay", "--help").out)
        val s = session("turning", turning.copy(durationS = 12.0))
        assertEquals(ExitCode.USAGE, fusion("calibrate", s.toString(), "--mag-model", "cube").code)
        assertEquals(ExitCode.USAGE, fusion("calibrate", s.toString(), "--min-coverage", "2").code)
        assertEquals(ExitCode.USAGE, fusion("calibrate", s.toString(), "-o", s.toString()).code)
        assertEquals(ExitCode.IO_ERROR, fusion("calibrate", dir.resolve("missing").toString()).code)
        // Outputs named as compressed are refused (written plain); the input options of every reading command apply.
        val gz = fusion("calibrate", s.toString(), "-o", dir.resolve("c.json.gz").toString())
        assertEquals(ExitCode.USAGE, gz.code)
        assertTrue("ends in .gz, but the calibration JSON is written plain" in gz.err, gz.err)
        assertEquals(ExitCode.USAGE, fusion("allan", s.toString(), "--plot", dir.resolve("p.svg.gz").toString()).code)
        val limited = fusion("calibrate", s.toString(), "--max-uncompressed", "40G", "--platform", "android", "--quiet")
        assertTrue(limited.code != ExitCode.USAGE, limited.err)
        assertTrue("--platform is for Sensor Logger exports" in limited.err, limited.err)
    }

    @Test
    fun `malformed and non-finite input`() {
        val s = session("turning", turning)
        // A malformed row stops with FILE:LINE:COLUMN and nothing is written.
        val gyro = s.resolve("gyroscope_uncalibrated.csv")
        val lines = Files.readAllLines(gyro).toMutableList()
        lines[5] = lines[5].replaceFirst(",", ",x")
        Files.write(gyro, lines)
        for (c in listOf("calibrate", "allan")) {
            val r = fusion(c, s.toString(), "-o", dir.resolve("$c.out").toString())
            assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
            assertTrue(Regex("""gyroscope_uncalibrated\.csv:6:\d+: """).containsMatchIn(r.err), r.err)
            assertTrue(!Files.exists(dir.resolve("$c.out")))
        }
        // A NaN reading is skipped by the fits and held at the previous sample by the Allan deviation.
        lines[5] = lines[5].replaceFirst(",x", ",")
        val fields = lines[5].split(',').toMutableList()
        fields[1] = "NaN"
        lines[5] = fields.joinToString(",")
        Files.write(gyro, lines)
        val r = fusion("calibrate", s.toString(), "--quiet")
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue((CalibrationJson.parse(r.out, "out").gyroscope!!.bias - gyroBias).norm() < 3e-4)
        // The turning phone has no noise figures to give: refused, naming the axes.
        val a = fusion("allan", s.toString(), "--quiet")
        assertEquals(ExitCode.DATA_ERROR, a.code, a.err)
        assertTrue("no white-noise line" in a.err && "gyroscope y" in a.err, a.err)
        // Lying still for 70 s, one NaN reading: held at the previous sample, counted as a gap.
        val still = session("still", turning.copy(durationS = 70.0, restWindows = listOf(TimeWindow(0.0, 71.0)), hardIronWindow = TimeWindow(0.0, 71.0)))
        val stillGyro = still.resolve("gyroscope_uncalibrated.csv")
        val stillLines = Files.readAllLines(stillGyro).toMutableList()
        stillLines[5] = stillLines[5].split(',').toMutableList().also { it[1] = "NaN" }.joinToString(",")
        Files.write(stillGyro, stillLines)
        val n = fusion("allan", still.toString(), "--quiet")
        assertEquals(ExitCode.OK, n.code, n.err)
        assertTrue("# 7000 samples at 100 Hz, 0 gaps" in n.out && "# 7000 samples at 100 Hz, 1 gaps" in n.out, n.out)
    }
}
