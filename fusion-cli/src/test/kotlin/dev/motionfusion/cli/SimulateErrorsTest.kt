package dev.motionfusion.cli

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.calib.Matrix3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import kotlin.math.cbrt

/**
 * `fusion simulate` with sensor errors and `--motion calibration`, then `fusion calibrate` on
 * its output: what one command put in, the other finds, within the bounds of docs/CALIBRATION.md.
 */
class SimulateErrorsTest {
    @TempDir
    lateinit var dir: Path

    private val hardIron = Vector3(35.0, -20.0, 60.0)
    private val softIron = Matrix3.symmetric(1.1, 0.92, 1.0, 0.05, 0.0, -0.03)
    private val gyroBias = Vector3(-0.012, 0.02, 0.004)
    private val accOffset = Vector3(0.12, -0.2, 0.15)
    private val accScale = Matrix3.diagonal(1.02, 0.97, 1.01)

    @Test
    fun `a calibration recording replays like a real one, its gyroscope recording every turn between faces`() {
        // Before, the truth jumped from one face to the next while the gyroscope read nothing: eval gave 78°.
        val session = dir.resolve("cal-replay")
        assertEquals(ExitCode.OK, fusion("simulate", "-o", session.toString(), "--motion", "calibration", "--duration", "60", "--seed", "3").code)
        val r = fusion("eval", "--csv", session.toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val total = r.out.lines()[1].split(',')[1].toDouble()
        assertTrue(total < 5.0, "total error over the calibration motion: ${r.out}")
    }

    @Test
    fun `calibrate recovers the errors simulate put in`() {
        val zip = dir.resolve("cal-session.zip")
        val s = fusion(
            "simulate", "-o", zip.toString(), "--motion", "calibration", "--duration", "100",
            "--hard-iron", "35,-20,60", "--soft-iron", "1.1,0.92,1.0,0.05,0,-0.03", "--gyro-bias", "-0.012,0.02,0.004",
            "--acc-offset", "0.12,-0.2,0.15", "--acc-scale", "1.02,0.97,1.01", "--gyro-noise-density", "0.0003", "--acc-noise-density", "0.002",
        )
        assertEquals(ExitCode.OK, s.code, s.err)
        assertTrue("--motion calibration --hard-iron 35,-20,60" in s.out, s.out)
        val r = fusion("calibrate", zip.toString(), "-o", dir.resolve("cal.json").toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        val cal = CalibrationJson.parse(Files.readString(dir.resolve("cal.json")), "cal.json")
        val m = cal.magnetometer!!
        val g = cal.gyroscope!!
        val a = cal.accelerometer!!
        val magOffset = (m.correction.offset - hardIron).norm()
        val wk = m.correction.matrix * softIron
        val shape = (wk * (1.0 / cbrt(wk.determinant()))).maxDifference(Matrix3.IDENTITY)
        val bias = (g.bias - gyroBias).norm()
        val acc = (a.correction.offset - accOffset).norm()
        val scale = a.correction.matrix.maxDifference(accScale.inverse())
        println("simulate → calibrate: hard iron within %.3f µT, soft-iron shape %.4f, coverage %.2f; gyroscope bias within %.1e rad/s (%.0f s still); accelerometer offset within %.4f m/s², scale %.5f"
            .format(magOffset, shape, m.coverage, bias, g.stillTimeS, acc, scale))
        assertTrue(magOffset < 0.5, "hard iron off by $magOffset µT")
        assertTrue(shape < 0.01, "soft iron shape off by $shape")
        assertTrue(bias < 3e-4, "gyroscope bias off by $bias rad/s")
        assertEquals(6, a.poses)
        assertTrue(acc < 0.01, "accelerometer offset off by $acc m/s²")
        assertTrue(scale < 0.002, "accelerometer scale off by $scale")
    }

    @Test
    fun `bad sensor-error options are usage errors`() {
        val out = dir.resolve("x.zip").toString()
        for ((args, message) in listOf(
            listOf("--hard-iron", "1,2") to "--hard-iron expects 3 numbers, got 2",
            listOf("--soft-iron", "1,2,3,4") to "--soft-iron expects 3 or 6 numbers, got 4",
            listOf("--gyro-bias", "0.1,x,0") to "--gyro-bias expects numbers separated by commas",
            listOf("--acc-scale", "1,-1,1") to "--acc-scale must be finite with a positive determinant",
            listOf("--gyro-noise-density", "-1") to "--gyro-noise-density must be ≥ 0",
            listOf("--motion", "figure8") to "--motion must be 'calibration'",
            listOf("--motion", "calibration", "--duration", "30") to "--duration must be over 43 s with --motion calibration",
        )) {
            val r = fusion("simulate", "-o", out, *args.toTypedArray())
            assertEquals(ExitCode.USAGE, r.code, "$args: ${r.err}")
            assertTrue(message in r.err, "$args: ${r.err}")
            assertTrue(!Files.exists(dir.resolve("x.zip")), "$args wrote a file")
        }
    }

    @Test
    fun `violent motions, sensor limits and a weak field are simulated and bad ones refused`() {
        val table = dir.resolve("violent.csv")
        val s = fusion(
            "simulate", "-o", table.toString(), "--duration", "20", "--rate", "200", "--violent", "shake@4,drop@10,throw@15",
            "--acc-range", "78.5", "--gyro-scale-error", "0.03", "--field", "15,30",
        )
        assertEquals(ExitCode.OK, s.code, s.err)
        assertTrue("--violent shake@4,drop@10,throw@15" in s.out, s.out)
        val rows = Files.readAllLines(table).drop(1).map { l -> l.split(',').map { it.toDouble() } }
        // Clipped at ±78.5 m/s², still (no rotation) outside the motions, 15 µT field.
        assertTrue(rows.all { r -> (4..6).all { kotlin.math.abs(r[it]) <= 78.5 + 0.2 } }, "accelerometer beyond its range")
        assertTrue(rows.any { r -> (4..6).any { kotlin.math.abs(r[it]) > 78.0 } }, "the drop's impact should clip")
        val still = rows.filter { it[0] in 8.0..9.0 }
        assertTrue(still.all { r -> kotlin.math.sqrt(r[1] * r[1] + r[2] * r[2] + r[3] * r[3]) < 0.1 }, "rotating between motions")
        assertTrue(still.all { r -> kotlin.math.abs(kotlin.math.sqrt(r[7] * r[7] + r[8] * r[8] + r[9] * r[9]) - 15.0) < 3.0 }, "field strength")
        for (bad in listOf("jump@3", "drop", "drop@19.9", "shake@-1")) {
            val r = fusion("simulate", "-o", dir.resolve("bad.csv").toString(), "--violent", bad)
            assertEquals(ExitCode.USAGE, r.code, "$bad: ${r.err}")
            assertTrue("--violent expects KIND@S" in r.err, r.err)
        }
    }
}
