package dev.motionfusion.core.replay

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale
import kotlin.math.PI
import kotlin.math.atan
import kotlin.math.sqrt

/**
 * The offline heading smoother on a recording shaped like BROAD's: at rest, in motion, at rest again, with
 * a gyroscope that drifts about the vertical only in motion and a magnetometer whose heading is off by a few
 * degrees only in motion (as where the field differs from the rest place's).
 */
class HeadingSmootherTest {
    @TempDir
    lateinit var dir: Path

    private fun deg(r: Double) = r * 180.0 / PI

    /** Heading error (°, the turn about the vertical between estimate and truth), RMS over the rows in [from, to) s. */
    private fun headingRms(orientations: List<DoubleArray>, times: List<Double>, truth: List<Quaternion>, from: Double, to: Double): Double {
        val idx = times.indices.filter { times[it] >= from && times[it] < to }
        return sqrt(idx.sumOf {
            val o = orientations[it]
            val e = Quaternion(o[0], o[1], o[2], o[3]) * truth[it].conjugate()
            val h = deg(2.0 * atan(e.z / e.w))
            h * h
        } / idx.size)
    }

    private fun replay(file: Path, offline: OfflineSettings): List<DoubleArray> = Recording.open(file).use { rec ->
        val out = ArrayList<DoubleArray>()
        val listener = object : ReplayListener {
            override fun step(step: ReplayStep) {
                out += step.orientation.copyOf()
            }
        }
        rec.events().use { Replayer().runOffline(it, rec.originNs, listener, offline = offline) }
        out
    }

    @Test
    fun `between two rests the smoother takes out the gyroscope's drift and the magnetometer's error in motion`() {
        val rests = listOf(TimeWindow(0.0, 25.0), TimeWindow(105.0, 130.0))
        val samples = MotionSimulator(SimulationSettings(durationS = 130.0, rateHz = 100.0, seed = 5, angularRate = 0.8, restWindows = rests)).run()
        val drift = 0.15 * PI / 180.0 // rad/s about the vertical, in motion only
        val magTurn = Quaternion.fromAxisAngle(Vector3(0.0, 0.0, 1.0), -4.0 * PI / 180.0) // the field's heading in motion
        val file = dir.resolve("rest-motion-rest.csv")
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for (s in samples) {
                val t = s.timestampNs * 1e-9
                val moving = rests.none { t in it }
                val g = if (moving) s.gyro + s.truth.inverseRotate(Vector3(0.0, 0.0, drift)) else s.gyro
                val m = if (moving) s.truth.inverseRotate(magTurn.rotate(s.truth.rotate(s.mag))) else s.mag
                val v = listOf(g.x, g.y, g.z, s.acc.x, s.acc.y, s.acc.z, m.x, m.y, m.z)
                w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it } + "\n")
            }
        }
        val times = samples.map { it.timestampNs * 1e-9 }
        val truth = samples.map { it.truth }
        val with = headingRms(replay(file, OfflineSettings()), times, truth, 25.0, 105.0)
        val without = headingRms(replay(file, OfflineSettings(headingSmoothing = 0.0)), times, truth, 25.0, 105.0)
        val alone = headingRms(replay(file, OfflineSettings(headingSmoothing = 1.0)), times, truth, 25.0, 105.0)
        val msg = String.format(Locale.ROOT, "heading RMSE in motion: smoother alone %.2f°, default weight %.2f°, without %.2f°", alone, with, without)
        println(msg)
        assertTrue(without > 2.0, msg)
        assertTrue(alone < 0.4 * without, msg)
        assertTrue(with < 0.75 * without, msg)
    }

    @Test
    fun `timestamps that repeat or step back a little leave the smoothed heading finite`() {
        val samples = MotionSimulator(SimulationSettings(durationS = 40.0, rateHz = 100.0, seed = 9, restWindows = listOf(TimeWindow(0.0, 10.0), TimeWindow(30.0, 40.0)))).run()
        val file = dir.resolve("step-back.csv")
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for ((i, s) in samples.withIndex()) {
                // Every 500th row repeats the time before it; every 700th steps 5 ms back.
                val t = when {
                    i > 0 && i % 500 == 0 -> samples[i - 1].timestampNs * 1e-9
                    i > 0 && i % 700 == 0 -> samples[i - 1].timestampNs * 1e-9 - 0.005
                    else -> s.timestampNs * 1e-9
                }
                val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x, s.mag.y, s.mag.z)
                w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it } + "\n")
            }
        }
        val out = replay(file, OfflineSettings(headingSmoothing = 1.0))
        val truth = samples.map { it.truth }
        val bad = out.indices.filter { i -> out[i].any { !it.isFinite() } }
        assertTrue(bad.isEmpty(), "rows without a finite orientation: ${bad.take(5)}")
        val worst = out.indices.filter { it > 100 }.maxOf { i -> deg(Quaternion(out[i][0], out[i][1], out[i][2], out[i][3]).angleTo(truth[i])) }
        assertTrue(worst < 5.0, String.format(Locale.ROOT, "largest error %.2f°", worst))
    }
}
