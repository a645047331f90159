package dev.motionfusion.core.eval

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.util.Locale
import java.util.zip.GZIPOutputStream
import kotlin.math.PI

class BroadMetricTest {
    private val truth = List(200) { Quaternion.fromAxisAngle(Vector3(1.0, -2.0, 0.5), 0.01 * it) }
    private fun rows(qs: List<Quaternion>) = qs.map { it.toDoubleArray() }.toTypedArray()
    private val all = BooleanArray(200) { true }
    private val deg10 = 10.0 * PI / 180.0

    @Test
    fun `an error about the vertical is heading only`() {
        val est = truth.map { Quaternion.fromAxisAngle(Vector3.UNIT_Z, deg10) * it }
        val r = BroadMetric.rmse(rows(est), rows(truth), all, removeHeadingOffset = false)
        assertEquals(10.0, r.totalDeg, 1e-9)
        assertEquals(10.0, r.headingDeg, 1e-9)
        assertEquals(0.0, r.inclinationDeg, 1e-6)
        assertEquals(200, r.samples)
        val sixD = BroadMetric.rmse(rows(est), rows(truth), all, removeHeadingOffset = true)
        assertEquals(0.0, sixD.totalDeg, 1e-6)
    }

    @Test
    fun `an error about a horizontal axis is inclination only, and unscored or unknown samples are skipped`() {
        val est = truth.mapIndexed { i, q -> Quaternion.fromAxisAngle(Vector3.UNIT_X, if (i < 100) deg10 else 3 * deg10) * q }
        val truthRows = rows(truth).also { it[5] = DoubleArray(4) { Double.NaN } }
        val scored = BooleanArray(200) { it < 100 }
        val r = BroadMetric.rmse(rows(est), truthRows, scored, removeHeadingOffset = true)
        assertEquals(10.0, r.inclinationDeg, 1e-9)
        assertEquals(0.0, r.headingDeg, 1e-6)
        assertEquals(99, r.samples)
    }

    @Test
    fun `loads a trial folder with gzip and plain CSV and scores the filter on it`(@TempDir dir: File) {
        val data = MotionSimulator(SimulationSettings(durationS = 30.0, restWindows = listOf(TimeWindow(0.0, 5.0)), gyroBias = Vector3(0.01, 0.0, 0.0))).run()
        fun f(v: Double) = String.format(Locale.ROOT, "%.9g", v)
        GZIPOutputStream(File(dir, "input.csv.gz").outputStream()).bufferedWriter().use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for (s in data) w.write(listOf(s.timestampNs * 1e-9, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x, s.mag.y, s.mag.z).joinToString(",") { f(it) } + "\n")
        }
        File(dir, "truth.csv").bufferedWriter().use { w ->
            w.write("t_s,qw,qx,qy,qz,movement\n")
            for ((i, s) in data.withIndex()) {
                val q = if (i == 10) listOf("", "", "", "") else s.truth.toDoubleArray().map { f(it) }
                w.write((listOf(f(s.timestampNs * 1e-9)) + q + (if (s.timestampNs >= 5_000_000_000L) "1" else "0")).joinToString(",") + "\n")
            }
        }
        assertEquals(listOf(dir), Evaluation.findTrials(listOf(dir)))
        val trial = Trial.load(dir)
        assertTrue(trial.hasMag)
        trial.open().use { rows -> repeat(11) { assertTrue(rows.next()) }; assertTrue(rows.truth[0].isNaN()) }
        val nine = Evaluation.evaluate(trial, FilterSettings())
        assertEquals(data.count { it.timestampNs >= 5_000_000_000L }, nine.error.samples)
        assertTrue(nine.error.totalDeg < 1.0, "9D error ${nine.error}")
        val six = Evaluation.evaluate(trial, FilterSettings(mode = FilterMode.IMU))
        assertTrue(six.error.totalDeg < 1.0, "6D error ${six.error}")
        assertTrue(Evaluation.table(listOf(nine, six)).contains("| **mean** |"))
    }
}
