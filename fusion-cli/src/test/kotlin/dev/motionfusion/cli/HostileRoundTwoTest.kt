package dev.motionfusion.cli

import org.junit.jupiter.api.AfterAll
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.TestInstance
import java.io.ByteArrayOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.attribute.FileTime
import java.util.Locale
import java.util.Random
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * The second round of hostile and tricky runs (no silently wrong result in eval, allan,
 * calibration files, batch folders and killed runs). One test per case; each checks the exit code,
 * the message, that no stack trace is printed and, where a number is the result, the number.
 * The counts over the suite are printed at the end, as HostileCasesTest does.
 */
@TestInstance(TestInstance.Lifecycle.PER_CLASS)
class HostileRoundTwoTest {
    private val tmp: Path = Files.createTempDirectory("fusion-hostile-2")

    private var runs = 0
    private var stackTraces = 0

    private fun p(name: String): String = tmp.resolve(name).toString()

    /** An in-process run, counted; [outputs] lets a test give the process start time. */
    private fun run(vararg args: String, outputs: Outputs = Outputs()): CliResult {
        val out = ByteArrayOutputStream()
        val err = ByteArrayOutputStream()
        val code = Cli(PrintStream(out, true, "UTF-8"), PrintStream(err, true, "UTF-8"), outputs).run(args.toList())
        val r = CliResult(code, out.toString("UTF-8"), err.toString("UTF-8"))
        runs++
        if (r.err.contains("\tat ") || r.err.contains("Exception")) stackTraces++
        assertFalse(r.err.contains("\tat ") || r.err.contains("Exception"), "no stack trace: ${r.err}")
        return r
    }

    private fun ok(vararg args: String): CliResult = run(*args).also { assertEquals(ExitCode.OK, it.code, it.err) }

    private fun fails(code: Int, message: String, vararg args: String): CliResult = run(*args).also {
        assertEquals(code, it.code, it.err)
        assertTrue(Regex(message).containsMatchIn(it.err), "message /$message/ in: ${it.err}")
    }

    private fun write(name: String, text: String): Path = tmp.resolve(name).also { Files.createDirectories(it.parent); Files.writeString(it, text) }

    private fun f(v: Double) = String.format(Locale.ROOT, "%.6f", v)

    @AfterAll
    fun numbers() {
        tmp.toFile().deleteRecursively()
        println("hostile cases, round two: $runs runs, $stackTraces stack traces")
    }

    // --- eval -------------------------------------------------------------------------------------

    /** A trial folder: the input table [table], identity truth at its times, and a rotation vector [yawDeg] off the truth. */
    private fun trial(dir: String, table: Path, yawDeg: Double?, movement: Int = 1) {
        val times = Files.readAllLines(table).drop(1).filter { it.isNotBlank() }.map { it.substringBefore(',') }
        Files.createDirectories(tmp.resolve(dir))
        Files.copy(table, tmp.resolve("$dir/input.csv"))
        write("$dir/truth.csv", "t_s,qw,qx,qy,qz,movement\n" + times.joinToString("") { "$it,1,0,0,0,$movement\n" })
        if (yawDeg != null) {
            val h = Math.toRadians(yawDeg) / 2
            write("$dir/rotation_vector.csv", "t_s,qw,qx,qy,qz\n" + times.joinToString("") { "$it,${cos(h)},0,0,${sin(h)}\n" })
        }
    }

    private fun simulatedTable(name: String, seconds: Int = 5): Path {
        val t = tmp.resolve(name)
        Files.createDirectories(t.parent)
        if (!Files.exists(t)) ok("simulate", "-o", t.toString(), "--duration", "$seconds", "--rate", "50")
        return t
    }

    @Test
    fun `eval keys the rotation vector by the trial's path, not its name`() {
        val table = simulatedTable("eval-table.csv")
        trial("dsA/t01", table, 0.0)
        trial("dsB/t01", table, 20.0)
        val r = ok("eval", p("dsA"), p("dsB"))
        val rows = r.out.lines().filter { it.startsWith("| ") && "t01" in it }
        assertEquals(2, rows.size, r.out)
        fun rv(row: String) = row.split('|').map { it.trim() }[5].toDouble()
        assertEquals(0.0, rv(rows.single { "dsA" in it }), 0.01, r.out)
        assertEquals(20.0, rv(rows.single { "dsB" in it }), 0.01, r.out)
    }

    @Test
    fun `eval of a data set names its half trials and scores its sessions, so the mean is over what the user sees`() {
        val table = simulatedTable("eval-table.csv")
        trial("halves/a", table, null)
        trial("halves/b", table, null)
        Files.delete(tmp.resolve("halves/b/truth.csv"))
        Files.createDirectories(tmp.resolve("halves/notes"))
        ok("simulate", "-o", p("halves/s"), "--duration", "5", "--rate", "50")
        ok("simulate", "-o", p("halves/z.zip"), "--duration", "5", "--rate", "50")
        val r = run("eval", p("halves"))
        assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
        assertTrue(Regex("halves/b: failed .*input\\.csv\\[\\.gz\\] without truth\\.csv\\[\\.gz\\]: half a trial, not scored").containsMatchIn(r.err), r.err)
        val names = r.out.lines().filter { it.startsWith("| ") }.map { it.split('|')[1].trim() }
        assertEquals(listOf("trial", "a", "s", "z", "**mean**"), names, r.out)
        assertFalse("notes" in r.err + r.out, "a folder that is no recording stays out: ${r.err}")
        // A session's truth.csv is on the phone's clock: --truth says to score the session itself.
        ok("replay", p("halves/s"), "-o", p("halves-s.csv"))
        fails(ExitCode.DATA_ERROR, "a session's stream \\(timestamp_ns, the phone's clock\\).*fusion eval SESSION", "eval", "--truth", p("halves/s/truth.csv"), p("halves-s.csv"))
    }

    @Test
    fun `--platform with an input that is no Sensor Logger export is said not to be used`() {
        val table = simulatedTable("platform-table.csv")
        val r = ok("replay", table.toString(), "--platform", "ios", "-o", p("platform-out.csv"))
        assertTrue("--platform is for Sensor Logger exports; a plain IMU table says its own axes, so it is not used" in r.err, r.err)
        assertFalse("--platform" in ok("replay", table.toString(), "-o", p("platform-out2.csv")).err)
    }

    @Test
    fun `a magnetometer that read nothing refuses 9D, and 6D replays without it as the message says`() {
        val rows = Files.readAllLines(simulatedTable("magzero-src.csv")).mapIndexed { i, l ->
            if (i == 0) l else l.split(',').let { f -> (f.take(7) + listOf("0", "0", "0")).joinToString(",") }
        }
        val table = tmp.resolve("magzero.csv").also { Files.write(it, rows) }
        fails(ExitCode.DATA_ERROR, "is zero throughout: no field was recorded; replay in 6D \\(--mode 6d\\)", "replay", table.toString(), "-o", p("magzero-9d.csv"))
        ok("replay", table.toString(), "--mode", "6d", "-o", p("magzero-6d.csv"))
        assertTrue(Files.readAllLines(tmp.resolve("magzero-6d.csv")).size > 200)
    }

    @Test
    fun `eval of a trial without a scored sample is an error, not a NaN table`() {
        trial("unscored/t01", simulatedTable("eval-table.csv"), null, movement = 0)
        val r = fails(ExitCode.DATA_ERROR, "unscored/t01.*no scored sample", "eval", p("unscored/t01"))
        assertFalse(r.out.contains("NaN"), r.out)
    }

    @Test
    fun `eval of a rotation vector that shares no instant with its truth is a data error, not an internal one`() {
        val table = simulatedTable("eval-table.csv")
        trial("rv-off/t01", table, 0.0)
        val shifted = Files.readAllLines(tmp.resolve("rv-off/t01/rotation_vector.csv")).mapIndexed { i, l ->
            if (i == 0) l else (l.substringBefore(',').toDouble() + 0.0123).toString() + "," + l.substringAfter(',')
        }
        Files.write(tmp.resolve("rv-off/t01/rotation_vector.csv"), shifted)
        fails(ExitCode.DATA_ERROR, "rv-off/t01.*rotation_vector\\.csv: no row at the time of a scored truth row", "eval", p("rv-off/t01"))
    }

    /** An orientation table (fusion replay's output) of the simulated table, and its rows reversed / its times in ms. */
    private fun orientation(): Path {
        val o = tmp.resolve("orient.csv")
        if (!Files.exists(o)) ok("replay", "--quiet", simulatedTable("eval-table.csv").toString(), "-o", o.toString())
        return o
    }

    @Test
    fun `eval --truth matches rows by time, says how many it scored and refuses tables out of order`() {
        val o = orientation()
        val lines = Files.readAllLines(o).filter { it.isNotBlank() }
        val truth = write("truth-yaw.csv", "t_s,qw,qx,qy,qz\n" + lines.drop(1).joinToString("") { it.split(',').take(5).joinToString(",") + "\n" })
        val same = ok("eval", "--csv", "--truth", truth.toString(), o.toString())
        assertEquals("0.000000", same.out.lines()[1].split(',')[1], same.out)
        assertTrue(Regex("scored \\d+ rows: (\\d+) of \\1 truth rows and \\1 orientation rows share a t_s").containsMatchIn(same.err), same.err)
        val reversed = write("orient-reversed.csv", (listOf(lines[0]) + lines.drop(1).reversed()).joinToString("\n", postfix = "\n"))
        fails(ExitCode.DATA_ERROR, "orient-reversed\\.csv:\\d+:\\d+: column t_s: .* before the row above .*time order", "eval", "--truth", truth.toString(), reversed.toString())
        val ms = write("truth-ms.csv", "t_s,qw,qx,qy,qz\n" + lines.drop(1).joinToString("") { l -> val c = l.split(','); "${c[0].toDouble() * 1000},${c.subList(1, 5).joinToString(",")}\n" })
        fails(ExitCode.DATA_ERROR, "orient\\.csv: \\d+ of \\d+ truth rows .* not aligned in time", "eval", "--truth", ms.toString(), o.toString())
    }

    @Test
    fun `eval --after takes two finite times in order`() {
        val o = orientation()
        fails(ExitCode.USAGE, "--after takes FROM:TO in seconds \\(two finite numbers\\), not 'NaN:5'", "eval", "--rows", simulatedTable("eval-table.csv").toString(), "--after", "NaN:5", o.toString())
        fails(ExitCode.USAGE, "--after 15:3: FROM must be before TO", "eval", "--rows", simulatedTable("eval-table.csv").toString(), "--after", "15:3", o.toString())
    }

    @Test
    fun `a session named with a pipe keeps the Markdown table's columns`() {
        ok("simulate", "-o", p("pipe|name"), "--duration", "5", "--rate", "50")
        val r = ok("eval", p("pipe|name"))
        val row = r.out.lines().single { "pipe" in it }
        assertTrue(row.contains("pipe\\|name"), row)
        assertEquals(5, row.split(Regex("(?<!\\\\)\\|")).size - 1, row)
    }

    // --- allan ------------------------------------------------------------------------------------

    /** A still table at 100 Hz: white noise of density [gyroN] rad/s/√Hz and [accN] m/s²/√Hz, one stretch per start in [starts] of [seconds] each. */
    private fun stillTable(name: String, starts: List<Double>, seconds: Double, gyroN: Double, accN: Double): Path {
        val rate = 100.0
        val random = Random(42)
        val sb = StringBuilder("t_s,gx,gy,gz,ax,ay,az\n")
        for (s in starts) {
            for (i in 0 until (seconds * rate).toInt()) {
                fun g() = random.nextGaussian() * gyroN * sqrt(rate)
                fun a() = random.nextGaussian() * accN * sqrt(rate)
                sb.append(String.format(Locale.ROOT, "%.4f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", s + i / rate, g(), g(), g(), a(), a(), 9.81 + a()))
            }
        }
        return write(name, sb.toString())
    }

    private fun yaml(text: String, key: String): Double = Regex("(?m)^$key: ([^ ]+)").find(text)!!.groupValues[1].toDouble()

    @Test
    fun `allan over a recording with a gap takes the rate and the clusters over the samples that exist`() {
        val t = stillTable("allan-gap.csv", listOf(0.0, 3635.0), 35.0, 0.001, 0.02)
        val r = ok("allan", "--quiet", t.toString())
        assertEquals(100.0, yaml(r.out, "update_rate"), 0.01, r.out)
        assertEquals(0.001, yaml(r.out, "gyroscope_noise_density"), 0.00025, r.out)
        assertEquals(0.02, yaml(r.out, "accelerometer_noise_density"), 0.005, r.out)
        assertTrue(r.out.contains("7000 samples at 100 Hz"), r.out)
    }

    @Test
    fun `allan with three 20 s gaps in 10 min gives the sample rate`() {
        val t = stillTable("allan-gaps.csv", listOf(0.0, 170.0, 340.0, 510.0), 150.0, 0.001, 0.02)
        val r = ok("allan", "--quiet", t.toString())
        assertEquals(100.0, yaml(r.out, "update_rate"), 0.01, r.out)
        assertEquals(0.001, yaml(r.out, "gyroscope_noise_density"), 0.00015, r.out)
    }

    @Test
    fun `allan of a phone that moved is refused, naming the axes without a white-noise line`() {
        val moving = simulatedTable("allan-moving.csv", 90)
        val r = fails(ExitCode.DATA_ERROR, "no white-noise line .* the phone moved or was handled", "allan", "--quiet", moving.toString(), "-o", p("allan-moving.yaml"))
        assertFalse(Files.exists(tmp.resolve("allan-moving.yaml")), "nothing written")
        assertFalse(".nan" in r.out, r.out)
    }

    @Test
    fun `plot refuses a truth on another time axis, as eval --truth does`() {
        val table = simulatedTable("plot-truth/table.csv")
        trial("plot-truth/trial", table, null)
        val truth = tmp.resolve("plot-truth/trial/truth.csv")
        val r = ok("plot", table.toString(), "--truth", truth.toString(), "-o", p("plot-truth/s.svg"))
        assertTrue("over every sample: total RMS" in r.out + r.err, r.out + r.err)
        val ms = write("plot-truth/truth-ms.csv", Files.readAllLines(truth).mapIndexed { i, l ->
            if (i == 0) l else (l.substringBefore(',').toDouble() * 1000).toString() + "," + l.substringAfter(',')
        }.joinToString("\n", postfix = "\n"))
        fails(ExitCode.DATA_ERROR, "t_s must be seconds on the replay's time axis", "plot", table.toString(), "--truth", ms.toString(), "-o", p("plot-truth/ms.svg"))
        assertFalse(Files.exists(tmp.resolve("plot-truth/ms.svg")))
    }

    @Test
    fun `eval removes the heading offset with --6d and where the trial's meta json says so, and refuses options that would do nothing`() {
        // A phone lying still, top edge north, and a truth 30° off in heading: 30° in 9D, none without the offset.
        val rows = (0 until 500).map { f(it * 0.01) }
        val h = Math.toRadians(30.0) / 2
        fun still(dir: String): Path {
            write("$dir/input.csv", "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" + rows.joinToString("") { "$it,0,0,0,0,0,9.81,0,20,-40\n" })
            write("$dir/truth.csv", "t_s,qw,qx,qy,qz\n" + rows.joinToString("") { "$it,${cos(h)},0,0,${sin(h)}\n" })
            return tmp.resolve(dir)
        }
        fun total(vararg args: String) = ok("eval", "--csv", *args).out.lines()[1].split(',')[1].toDouble()
        val plain = still("six-d/north")
        assertEquals(30.0, total(plain.toString()), 0.5)
        assertTrue(total("--6d", plain.toString()) < 0.5)
        val scored = still("six-d/tagged")
        write("six-d/tagged/meta.json", "{\"scoring\": \"6d: one constant heading offset removed per trial\"}")
        assertTrue(total(scored.toString()) < 0.5, "the trial's own scoring")
        // Options that a table scored as it is would ignore are refused.
        val est = tmp.resolve("six-d/est.csv")
        ok("replay", plain.toString(), "-o", est.toString())
        fails(ExitCode.USAGE, "--beta: --truth scores an orientation table as it is", "eval", "--truth", plain.resolve("truth.csv").toString(), est.toString(), "--beta", "0.5")
        fails(ExitCode.USAGE, "--truth and --6d go with a truth, not with --rows", "eval", "--rows", plain.resolve("input.csv").toString(), "--truth", plain.resolve("truth.csv").toString(), est.toString())
        // An all-zero quaternion is no orientation: skipped as an empty row is, not a NaN score.
        val lines = Files.readAllLines(est).toMutableList()
        lines[10] = lines[10].split(',').toMutableList().also { for (k in 1..4) it[k] = "0" }.joinToString(",")
        val zero = write("six-d/zero.csv", lines.joinToString("\n", postfix = "\n"))
        val z = ok("eval", "--truth", plain.resolve("truth.csv").toString(), zero.toString())
        assertFalse("NaN" in z.out, z.out)
    }

    @Test
    fun `a session whose magnetometer file holds its header alone replays in 6D from the first row`() {
        val session = tmp.resolve("mag-header/session")
        Files.createDirectories(session.parent)
        ok("simulate", "-o", session.toString(), "--duration", "5", "--rate", "50")
        val mag = session.resolve("magnetometer.csv")
        Files.write(mag, listOf(Files.readAllLines(mag)[0]))
        val meta = session.resolve("meta.json")
        Files.writeString(meta, Regex(""""magnetometer"\s*:\s*\{[^}]*?"samples"\s*:\s*\d+""").replace(Files.readString(meta)) { it.value.replace(Regex("""\d+$"""), "0") })
        val r = ok("replay", session.toString(), "-o", p("mag-header/out.csv"))
        assertTrue("no magnetometer: 6D" in r.err, r.err)
        assertTrue("0 before start" in r.err, r.err)
        // Calibrate refuses a gravity that is no earth's, naming the option.
        fails(ExitCode.USAGE, "--gravity must be the earth's, 9.7–9.9 m/s²", "calibrate", session.toString(), "--gravity", "20")
    }

    @Test
    fun `allan refuses a plot that is a link to its YAML`() {
        val t = stillTable("allan-still.csv", listOf(0.0), 70.0, 0.001, 0.02)
        val yaml = write("noise.yaml", "an earlier output\n")
        val link = Files.createSymbolicLink(tmp.resolve("noise-link.svg"), yaml)
        fails(ExitCode.USAGE, "-o .*noise\\.yaml and --plot .*noise-link\\.svg name the same file", "allan", t.toString(), "-o", yaml.toString(), "--plot", link.toString())
        assertEquals("an earlier output\n", Files.readString(yaml))
    }

    // --- calibration files --------------------------------------------------------------------------

    private fun session(name: String): Path {
        val s = tmp.resolve(name)
        if (!Files.exists(s)) ok("simulate", "-o", s.toString(), "--duration", "10", "--rate", "50")
        return s
    }

    private fun calibration(name: String, magOffset: String = "[10, -5, 3]", matrix: String = "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
                            gyroBias: String? = null, accOffset: String? = null, device: String? = null): Path = write(
        name,
        """
        |{
        |  "format": "motion-fusion-calibration",
        |  "format_version": 1,
        |  "source": "a test",
        |  "recording": "",
        |${if (device != null) "  \"device\": \"$device\",\n" else ""}  "magnetometer": {"stream": "magnetometer", "model": "FULL", "offset_uT": $magOffset, "matrix": $matrix}${if (gyroBias != null || accOffset != null) "," else ""}
        |${if (gyroBias != null) "  \"gyroscope\": {\"stream\": \"gyroscope\", \"bias_rad_s\": $gyroBias}" + (if (accOffset != null) "," else "") else ""}
        |${if (accOffset != null) "  \"accelerometer\": {\"stream\": \"accelerometer\", \"model\": \"FULL\", \"offset_m_s2\": $accOffset, \"matrix\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}" else ""}
        |}
        """.trimMargin(),
    )

    @Test
    fun `a calibration whose soft iron is not symmetric is refused, naming the member`() {
        val c = calibration("rotated.json", matrix = "[[0, -1, 0], [1, 0, 0], [0, 0, 1]]")
        fails(ExitCode.DATA_ERROR, "rotated\\.json:\\d+:\\d+: magnetometer\\.matrix: not a calibration matrix: not symmetric", "replay", session("s").toString(), "--calibration", c.toString(), "-o", p("cal-out.csv"))
        assertFalse(Files.exists(tmp.resolve("cal-out.csv")))
    }

    @Test
    fun `a calibration with a negative definite soft iron is refused`() {
        val c = calibration("flip.json", matrix = "[[-1, 0, 0], [0, -1, 0], [0, 0, 1]]")
        fails(ExitCode.DATA_ERROR, "flip\\.json:\\d+:\\d+: magnetometer\\.matrix: not a calibration matrix: not positive definite", "replay", session("s").toString(), "--calibration", c.toString())
    }

    @Test
    fun `offsets and biases beyond any phone's are blamed on the calibration, not the recording`() {
        val s = session("s").toString()
        fails(ExitCode.DATA_ERROR, "acc\\.json:\\d+:\\d+: accelerometer\\.offset_m_s2: 9\\.81 m/s²: .*this calibration is wrong", "replay", s, "--calibration", calibration("acc.json", accOffset = "[0, 0, 9.81]").toString())
        fails(ExitCode.DATA_ERROR, "mag\\.json:\\d+:\\d+: magnetometer\\.offset_uT: 1E\\+6 µT: .*this calibration is wrong", "replay", s, "--calibration", calibration("mag.json", magOffset = "[1e6, 0, 0]").toString())
        val r = fails(ExitCode.DATA_ERROR, "gyro\\.json:\\d+:\\d+: gyroscope\\.bias_rad_s: 500 rad/s: .*this calibration is wrong", "replay", s, "--calibration", calibration("gyro.json", gyroBias = "[500, 0, 0]").toString())
        assertFalse(r.err.contains("beyond any phone's range"), r.err)
    }

    @Test
    fun `a calibration from another device is applied with a note naming both`() {
        val c = calibration("pixel.json", device = "Google Pixel 8; magnetometer: AK09918")
        val r = ok("replay", session("s").toString(), "--calibration", c.toString(), "-o", p("pixel.csv"))
        assertTrue(r.err.contains("pixel.json was fitted on Google Pixel 8, but s was recorded on Motion Fusion MotionSimulator"), r.err)
        val same = ok("replay", session("s").toString(), "--calibration", calibration("sim.json", device = "Motion Fusion MotionSimulator; x").toString(), "-o", p("sim.csv"))
        assertFalse(same.err.contains("was fitted on"), same.err)
    }

    @Test
    fun `--calibration of a folder names it`() {
        fails(ExitCode.IO_ERROR, "${Regex.escape(p("s"))}: is a folder; --calibration takes a calibration file", "replay", session("s2").toString(), "--calibration", session("s").toString())
    }

    @Test
    fun `calibrate accepts a hard iron of 1,500 µT and finds it`() {
        ok("simulate", "--motion", "calibration", "--hard-iron", "1500,0,0", "-o", p("iron1500.csv"))
        val r = ok("calibrate", p("iron1500.csv"))
        val offset = Regex("\"offset_uT\": \\[\\s*([^,\\s]+)").find(r.out)!!.groupValues[1].trim().toDouble()
        assertEquals(1500.0, offset, 5.0, r.out)
    }

    @Test
    fun `calibrate and simulate name their options, not internal settings`() {
        fails(ExitCode.USAGE, "^fusion: --min-coverage must be in \\[0, 1\\]", "calibrate", p("any.csv"), "--min-coverage", "2")
        fails(ExitCode.USAGE, "^fusion: --soft-iron must be finite with a positive determinant", "simulate", "-o", p("x.csv"), "--soft-iron", "-1,1,1")
    }

    // --- simulate ---------------------------------------------------------------------------------

    @Test
    fun `simulate --motion calibration honours --hard-iron-window`() {
        ok("simulate", "--motion", "calibration", "--hard-iron", "300,0,0", "--hard-iron-window", "45,60", "-o", p("window.csv"))
        val rows = Files.readAllLines(tmp.resolve("window.csv")).drop(1).filter { it.isNotBlank() }.map { l -> l.split(',').let { it[0].toDouble() to it[7].toDouble() } }
        val inside = rows.filter { it.first >= 45.5 && it.first < 59.5 }.map { it.second }
        val outside = rows.filter { it.first < 44.5 || it.first >= 60.5 }.map { it.second }
        assertTrue(inside.isNotEmpty() && outside.isNotEmpty())
        assertTrue(inside.all { it > 200.0 }, "inside the window the hard iron applies")
        assertTrue(outside.all { abs(it) < 100.0 }, "outside the window it does not: ${outside.maxOf { abs(it) }}")
    }

    @Test
    fun `simulate refuses a sensor range of 0`() {
        fails(ExitCode.USAGE, "--gyro-range must be in \\(0, 200] \\(leave it out for no clipping\\)", "simulate", "-o", p("r0.csv"), "--gyro-range", "0")
        fails(ExitCode.USAGE, "--acc-range must be in \\(0, 2000]", "simulate", "-o", p("r0.csv"), "--acc-range", "0")
        assertFalse(Files.exists(tmp.resolve("r0.csv")))
    }

    // --- batches and outputs ----------------------------------------------------------------------

    @Test
    fun `a batch refused because its folder lies inside an input creates nothing`() {
        val c = session("sessC")
        val d = session("sessD")
        fails(ExitCode.USAGE, "lies inside the input", "replay", c.toString(), d.toString(), "-o", "$c/results/")
        assertFalse(Files.exists(c.resolve("results")), "no folder made inside the input")
    }

    @Test
    fun `a batch refused for a name clash leaves no new folder`() {
        val a = simulatedTable("clash-a/x.csv")
        val b = simulatedTable("clash-b/x.csv")
        fails(ExitCode.USAGE, "would both be written to", "replay", a.toString(), b.toString(), "-o", p("clash-out") + "/")
        assertFalse(Files.exists(tmp.resolve("clash-out")))
    }

    @Test
    fun `two inputs with -o naming a file are refused rather than made a folder`() {
        val a = simulatedTable("two-a.csv")
        val b = simulatedTable("two-b.csv")
        fails(ExitCode.USAGE, "with several inputs -o names a folder: .*X\\.csv does not exist; give .*X\\.csv/", "replay", a.toString(), b.toString(), "-o", p("X.csv"))
        assertFalse(Files.exists(tmp.resolve("X.csv")))
    }

    @Test
    fun `-o - is standard output for a replay and refused where an output must be a file`() {
        val table = simulatedTable("stdout/table.csv")
        val plain = ok("replay", table.toString()).out
        assertEquals(plain, ok("replay", table.toString(), "-o", "-").out)
        assertFalse(Files.exists(Path.of("-")), "a file named '-' was written")
        fails(ExitCode.USAGE, "with several inputs give -o FOLDER/", "replay", table.toString(), table.toString(), "-o", "-")
        fails(ExitCode.USAGE, "'-' \\(standard output\\) is not an output of this command here", "replay", table.toString(), "--rows", "-")
        fails(ExitCode.USAGE, "'-' \\(standard output\\) is not an output of this command here", "plot", table.toString(), "-o", "-")
    }

    // --- earlier corpus ---------------------------------------------------------------------------

    @Test
    fun `-o and --rows naming the same file are refused and leave the file as it was`() {
        val table = simulatedTable("same-out/table.csv")
        val same = write("same-out/same.csv", "earlier\n")
        fails(ExitCode.USAGE, "name the same file", "replay", table.toString(), "-o", same.toString(), "--rows", same.toString())
        fails(ExitCode.USAGE, "name the same file", "replay", table.toString(), "-o", same.toString(), "--rows", tmp.resolve("same-out/../same-out/same.csv").toString())
        assertEquals("earlier\n", Files.readString(same))
        ok("replay", table.toString(), "-o", "/dev/null", "--rows", "/dev/null")
    }

    @Test
    fun `a link out of a session folder is named, in the note and in the error it causes`() {
        val table = simulatedTable("links/table.csv")
        val session = tmp.resolve("links/session")
        Files.createDirectories(session.parent)
        ok("simulate", "-o", session.toString(), "--duration", "5", "--rate", "50")
        val outside = tmp.resolve("links/outside")
        Files.createDirectories(outside)
        // The magnetometer linked out: the replay goes on in 6D and says which file it did not read.
        Files.move(session.resolve("magnetometer.csv"), outside.resolve("magnetometer.csv"))
        Files.createSymbolicLink(session.resolve("magnetometer.csv"), outside.resolve("magnetometer.csv"))
        val r = ok("replay", session.toString(), "-o", p("links/out.csv"))
        assertTrue("magnetometer.csv is a link out of the folder, not followed" in r.err, r.err)
        // The gyroscope linked out too: the note comes before the error it causes.
        Files.move(session.resolve("gyroscope.csv"), outside.resolve("gyroscope.csv"))
        Files.createSymbolicLink(session.resolve("gyroscope.csv"), outside.resolve("gyroscope.csv"))
        val e = fails(ExitCode.DATA_ERROR, "has no gyroscope samples", "replay", session.toString(), "-o", p("links/out2.csv"))
        assertTrue(e.err.indexOf("gyroscope.csv, magnetometer.csv are links out of the folder, not followed") in 0 until e.err.indexOf("no gyroscope samples"), e.err)
        // A folder whose every file is a link out: nothing is recognised, and the message says why.
        val bare = tmp.resolve("links/bare")
        Files.createDirectories(bare)
        for (n in listOf("gyroscope.csv", "magnetometer.csv")) Files.createSymbolicLink(bare.resolve(n), outside.resolve(n))
        fails(ExitCode.DATA_ERROR, "are links out of the folder, not followed", "replay", bare.toString(), "-o", p("links/out3.csv"))
        assertTrue(Files.exists(table))
        // A link to a session folder, given as the input, is that folder (as for a link to a file).
        val whole = tmp.resolve("links/whole")
        ok("simulate", "-o", whole.toString(), "--duration", "5", "--rate", "50")
        val alias = Files.createSymbolicLink(tmp.resolve("links/alias"), whole)
        ok("replay", whole.toString(), "-o", p("links/direct.csv"))
        ok("replay", alias.toString(), "-o", p("links/via-link.csv"))
        assertEquals(Files.readAllLines(tmp.resolve("links/direct.csv")), Files.readAllLines(tmp.resolve("links/via-link.csv")))
        // A link inside a folder to a session elsewhere is named, not skipped in silence.
        val holder = Files.createDirectories(tmp.resolve("links/holder"))
        Files.createSymbolicLink(holder.resolve("sess"), whole)
        fails(ExitCode.DATA_ERROR, "sess is a link out of the folder, not followed", "replay", holder.toString(), "-o", p("links/out4.csv"))
    }

    @Test
    fun `compare in 6D compares the heading from a common start and says so`() {
        // The simulated session's rotation vector is the truth 2° off in heading. 6D has no north: its heading
        // starts wherever the first reading puts it (41° off here), so the offset at the start is removed.
        val session = tmp.resolve("compare6d/session")
        Files.createDirectories(session.parent)
        ok("simulate", "-o", session.toString(), "--duration", "5", "--rate", "50")
        val six = ok("compare", session.toString(), "--mode", "6d")
        val median = six.out.lines().first { it.startsWith("| heading |") }.split('|')[4].trim().toDouble()
        assertTrue("6D: heading from a common start" in six.out, six.out)
        assertTrue(median < 5.0, "6D heading difference from a common start: ${six.out}")
        assertFalse("common start" in ok("compare", session.toString()).out, "9D keeps north")
    }

    @Test
    fun `an accelerometer reading of 1e308 does not reach the linear acceleration`() {
        val rows = Files.readAllLines(simulatedTable("lin-table.csv")).toMutableList()
        rows[100] = rows[100].split(',').toMutableList().also { it[6] = "1e308" }.joinToString(",")
        val t = write("acc-1e308.csv", rows.joinToString("\n", postfix = "\n"))
        val r = ok("replay", t.toString(), "-o", p("lin.csv"))
        assertTrue(r.err.contains("1 beyond any phone's range"), r.err)
        val up = Files.readAllLines(tmp.resolve("lin.csv")).drop(1).filter { it.isNotBlank() }.map { it.split(',')[13].toDouble() }.filter { !it.isNaN() }
        assertTrue(up.all { abs(it) < 50.0 }, "largest |lin_acc_up| ${up.maxOf { abs(it) }}")
    }

    @Test
    fun `a session whose gyroscope file holds half of what meta json counts is replayed with a warning`() {
        val s = session("half")
        val g = s.resolve("gyroscope.csv")
        val lines = Files.readAllLines(g)
        Files.write(g, lines.take(1 + (lines.size - 1) / 2))
        val r = ok("replay", s.toString(), "-o", p("half.csv"))
        assertTrue(Regex("warning: half: meta\\.json counts 500 gyroscope samples, but gyroscope\\.csv holds 2\\d\\d").containsMatchIn(r.err), r.err)
    }

    @Test
    fun `recover of a session still being written is refused and counts nothing wrong`() {
        val s = session("writing")
        val meta = s.resolve("meta.json")
        Files.writeString(meta, Files.readString(meta).replace("\"complete\": true", "\"complete\": false"))
        val g = s.resolve("gyroscope.csv")
        val last = Files.readAllLines(g).last { it.isNotBlank() }.split(',')[0].toLong()
        Files.write(g, "${last + 20_000_000},0.1,0.".toByteArray(), java.nio.file.StandardOpenOption.APPEND) // the row being written
        val before = Files.readString(meta)
        // The recording goes on while recovery works: rows are appended after recovery cut the partial row.
        val recordingGoesOn = object : dev.motionfusion.core.io.FileOperations by dev.motionfusion.core.io.FileOperations.SYSTEM {
            override fun truncate(path: Path, size: Long) {
                dev.motionfusion.core.io.FileOperations.SYSTEM.truncate(path, size)
                Files.write(g, (1..101).joinToString("") { "${last + 20_000_000L * it},0.01,0.02,0.03,3\n" }.toByteArray(), java.nio.file.StandardOpenOption.APPEND)
            }
        }
        val e = org.junit.jupiter.api.assertThrows<dev.motionfusion.core.io.DataFormatException> {
            dev.motionfusion.core.session.SessionRecovery(recordingGoesOn).recover(s, dryRun = false)
        }
        runs++
        assertTrue(Regex("writing/gyroscope\\.csv: is still being written: .*meta\\.json is as it was\\); recover the session once its recording has stopped").containsMatchIn(e.message!!), e.message)
        assertEquals(before, Files.readString(meta), "meta.json does not count other rows than the file holds")
        // Once the recording has stopped, recovery counts every row the file holds.
        ok("recover", s.toString())
        val rows = Files.readAllLines(g).drop(1).count { it.isNotBlank() }
        assertTrue(Files.readString(meta).contains(Regex("\"file\": \"gyroscope\\.csv\",\\s*\"samples\": $rows,")), Files.readString(meta))
    }

    @Test
    fun `a file name with bytes that are not UTF-8 gets a message saying so`() {
        fails(ExitCode.IO_ERROR, "the name holds bytes that are not .* rename the file", "summary", p("a\uFFFD.csv"))
    }

    // --- temporary files --------------------------------------------------------------------------

    @Test
    fun `a run removes stale temporary files an interrupted earlier run left beside its output, and says so`() {
        val table = simulatedTable("stale-in.csv")
        val dir = Files.createDirectories(tmp.resolve("stale"))
        val hourAgo = FileTime.fromMillis(System.currentTimeMillis() - 3_600_000)
        val gone = listOf(".out.csv.999999999-a1b2c3.tmp", ".out.csv.d4e5f6.tmp").map { dir.resolve(it).also { f -> Files.writeString(f, "half a row"); Files.setLastModifiedTime(f, hourAgo) } }
        val mine = dir.resolve(".out.csv.${ProcessHandle.current().pid()}-abc.tmp").also { Files.writeString(it, "a running writer's"); Files.setLastModifiedTime(it, hourAgo) }
        val fresh = dir.resolve(".out.csv.beef.tmp").also { Files.writeString(it, "written after this run started") }
        val other = dir.resolve(".other.csv.1234.tmp").also { Files.writeString(it, "another output's"); Files.setLastModifiedTime(it, hourAgo) }
        val started = System.currentTimeMillis() - 60_000
        val r = run("replay", table.toString(), "-o", dir.resolve("out.csv").toString(), outputs = Outputs(startedMs = started))
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.err.contains("note: removed 2 temporary files an interrupted earlier run left beside"), r.err)
        for (f in gone) assertFalse(Files.exists(f), "$f removed")
        for (f in listOf(mine, fresh, other)) assertTrue(Files.exists(f), "$f kept")
    }

    @Test
    fun `a spooled standard input an interrupted earlier run left is removed when standard input is next read`() {
        val t = Path.of(System.getProperty("java.io.tmpdir"))
        val stale = t.resolve("fusion-input-999999999-12345.tmp").also { Files.writeString(it, "spooled"); Files.setLastModifiedTime(it, FileTime.fromMillis(0)) }
        val stdin = System.`in`
        System.setIn(java.io.ByteArrayInputStream(Files.readAllBytes(simulatedTable("stdin.csv"))))
        val r = try {
            run("replay", "-", "-o", p("stdin-out.csv"))
        } finally {
            System.setIn(stdin)
        }
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.err.contains("removed 1 spooled input an interrupted earlier run left: $stale"), r.err)
        assertFalse(Files.exists(stale))
    }

    // --- as its own process: file names as the system passes them, signals ------------------------

    /** `fusion ARGS` as its own process in [dir], with its own temporary folder [tmpdir]; [shell] wraps the command line for sh. */
    private fun process(dir: Path, tmpdir: Path, vararg args: String): ProcessBuilder {
        val java = Path.of(System.getProperty("java.home"), "bin", "java").toString()
        return ProcessBuilder(listOf(java, "-XX:-UsePerfData", "-Djava.io.tmpdir=$tmpdir", "-cp", System.getProperty("java.class.path"), "dev.motionfusion.cli.MainKt") + args)
            .directory(dir.toFile())
    }

    private fun finished(p: Process): CliResult {
        p.outputStream.close()
        val out = p.inputStream.readAllBytes()
        val err = p.errorStream.readAllBytes()
        val code = p.waitFor()
        val r = CliResult(code, String(out, Charsets.ISO_8859_1), String(err, Charsets.ISO_8859_1))
        runs++
        if (r.err.contains("\tat ") || r.err.contains("Exception")) stackTraces++
        assertFalse(r.err.contains("\tat ") || r.err.contains("Exception"), "no stack trace: ${r.err}")
        return r
    }

    @Test
    fun `a batch keeps the -- before inputs whose names start with a dash`() {
        val dir = Files.createDirectories(tmp.resolve("dash"))
        val src = simulatedTable("dash-src.csv")
        Files.copy(src, dir.resolve("-dash.csv"))
        Files.copy(src, dir.resolve("good.csv"))
        val r = finished(process(dir, tmp, "replay", "-o", "out/", "--", "-dash.csv", "good.csv").start())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(Files.size(dir.resolve("out/-dash.csv")) > 1000 && Files.size(dir.resolve("out/good.csv")) > 1000, r.err)
    }

    @Test
    fun `a real file name with a 0xFF byte is named as not UTF-8`() {
        val dir = Files.createDirectories(tmp.resolve("ff"))
        val java = Path.of(System.getProperty("java.home"), "bin", "java").toString()
        val sh = ProcessBuilder("sh", "-c", "printf 't_s,gx,gy,gz,ax,ay,az\\n' > \"$(printf 'a\\377.csv')\"; " +
            "exec \"$0\" -XX:-UsePerfData -cp \"$1\" dev.motionfusion.cli.MainKt summary \"$(printf 'a\\377.csv')\"", java, System.getProperty("java.class.path"))
            .directory(dir.toFile())
        sh.environment()["LC_ALL"] = "C.UTF-8"
        val r = finished(sh.start())
        assertEquals(ExitCode.IO_ERROR, r.code, r.err)
        assertTrue(r.err.contains("the name holds bytes that are not UTF-8"), r.err)
    }

    /** Waits (on the file system's events, not a clock) until [dir] holds a name matching [wanted]. */
    private fun awaitName(dir: Path, wanted: (String) -> Boolean) {
        dir.fileSystem.newWatchService().use { w ->
            dir.register(w, java.nio.file.StandardWatchEventKinds.ENTRY_CREATE)
            while (Files.list(dir).use { s -> s.noneMatch { wanted(it.fileName.toString()) } }) {
                val key = w.poll(120, java.util.concurrent.TimeUnit.SECONDS) ?: throw AssertionError("no ${dir.fileName} entry appeared in 120 s")
                key.pollEvents()
                key.reset()
            }
        }
    }

    private fun names(dir: Path): List<String> = Files.list(dir).use { s -> s.map { it.fileName.toString() }.sorted().toList() }

    @Test
    fun `SIGTERM leaves no temporary file beside the output nor in the temporary folder`() {
        val dir = Files.createDirectories(tmp.resolve("term"))
        val tmpdir = Files.createDirectories(tmp.resolve("term-tmp"))
        for (out in listOf("long.csv", "long")) {
            val p = process(dir, tmpdir, "simulate", "-o", out, "--duration", "86400", "--rate", "2000").start()
            awaitName(dir) { it.startsWith(".$out.") && it.endsWith(".tmp") }
            // A session folder: killed once its streams are being written.
            val aside = dir.resolve(names(dir).single { it.startsWith(".$out.") })
            if (Files.isDirectory(aside)) awaitName(aside) { it == "rotation_vector.csv" }
            p.destroy() // SIGTERM
            assertEquals(143, p.waitFor())
            assertEquals(emptyList<String>(), names(dir), "after SIGTERM of simulate -o $out")
        }
        val p = process(dir, tmpdir, "replay", "-").start()
        p.outputStream.write(Files.readAllBytes(simulatedTable("term-in.csv")))
        p.outputStream.flush() // and left open: the input is being spooled
        awaitName(tmpdir) { it.startsWith("fusion-input-") }
        p.destroy()
        assertEquals(143, p.waitFor())
        assertEquals(emptyList<String>(), names(tmpdir), "after SIGTERM of replay -")
        assertEquals(emptyList<String>(), names(dir))
    }

    @Test
    fun `a temporary file that cannot be written names the temporary folder`() {
        val dir = Files.createDirectories(tmp.resolve("full"))
        val tmpdir = Files.createDirectories(tmp.resolve("full-tmp"))
        val table = simulatedTable("full-in.csv", seconds = 120)
        val java = Path.of(System.getProperty("java.home"), "bin", "java").toString()
        // A file size limit (ulimit -f) makes a write past a few hundred KiB fail as a full device would; stdout is a pipe, not limited.
        fun limited(vararg args: String): CliResult = finished(
            ProcessBuilder(listOf("sh", "-c", "ulimit -f 512; exec \"$@\"", "sh", java, "-XX:-UsePerfData", "-Djava.io.tmpdir=$tmpdir", "-cp", System.getProperty("java.class.path"), "dev.motionfusion.cli.MainKt") + args)
                .directory(dir.toFile()).redirectInput(table.toFile()).start(),
        )
        val spooled = limited("replay", "-")
        assertEquals(ExitCode.IO_ERROR, spooled.code, spooled.err)
        assertTrue(spooled.err.contains("$tmpdir: standard input is read once into a temporary file here (java.io.tmpdir"), spooled.err)
        val offline = limited("replay", "--offline", table.toString())
        assertEquals(ExitCode.IO_ERROR, offline.code, offline.err)
        assertTrue(offline.err.contains("$tmpdir: the offline estimate's temporary file (java.io.tmpdir"), offline.err)
        assertEquals(emptyList<String>(), names(tmpdir))
    }
}
