package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
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

    private val rests = listOf(TimeWindow(0.0, 25.0), TimeWindow(105.0, 130.0))
    private val samples by lazy { MotionSimulator(SimulationSettings(durationS = 130.0, rateHz = 100.0, seed = 5, angularRate = 0.8, restWindows = rests)).run() }

    /**
     * The rest–motion–rest table: the gyroscope drifting 0.15°/s about the vertical and the field's heading 4° off, both in
     * motion only; [cell] may replace a row's text cells (index, the nine values as text) to put a fault in.
     */
    private fun restMotionRest(name: String, cell: (Int, List<String>) -> List<String> = { _, v -> v }): Path {
        val drift = 0.15 * PI / 180.0 // rad/s about the vertical, in motion only
        val magTurn = Quaternion.fromAxisAngle(Vector3(0.0, 0.0, 1.0), -4.0 * PI / 180.0) // the field's heading in motion
        val file = dir.resolve(name)
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for ((i, s) in samples.withIndex()) {
                val t = s.timestampNs * 1e-9
                val moving = rests.none { t in it }
                val g = if (moving) s.gyro + s.truth.inverseRotate(Vector3(0.0, 0.0, drift)) else s.gyro
                val m = if (moving) s.truth.inverseRotate(magTurn.rotate(s.truth.rotate(s.mag))) else s.mag
                val v = cell(i, listOf(g.x, g.y, g.z, s.acc.x, s.acc.y, s.acc.z, m.x, m.y, m.z).map { it.toString() })
                w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it } + "\n")
            }
        }
        return file
    }

    /** Heading RMSE in motion, °: the smoother alone, the default weight, without the smoother. */
    private fun inMotion(file: Path): Triple<Double, Double, Double> {
        val times = samples.map { it.timestampNs * 1e-9 }
        val truth = samples.map { it.truth }
        fun rms(o: OfflineSettings) = headingRms(replay(file, o), times, truth, 25.0, 105.0)
        return Triple(rms(OfflineSettings(headingSmoothing = 1.0)), rms(OfflineSettings()), rms(OfflineSettings(headingSmoothing = 0.0)))
    }

    @Test
    fun `between two rests the smoother takes out the gyroscope's drift and the magnetometer's error in motion`() {
        val (alone, with, without) = inMotion(restMotionRest("rest-motion-rest.csv"))
        val msg = String.format(Locale.ROOT, "heading RMSE in motion: smoother alone %.2f°, default weight %.2f°, without %.2f°", alone, with, without)
        println(msg)
        assertTrue(without > 2.0, msg)
        assertTrue(alone < 0.4 * without, msg)
        assertTrue(with < 0.75 * without, msg)
    }

    @Test
    fun `a field whose magnitude changes in motion gets no trust at rest, a consistent one keeps it`() {
        // The magnetometer's heading 4° off at rest only, and in motion a magnitude that swings by ±8 % (its heading
        // right): a field that changes as the device moves, as with a magnet carried along, where a rest holds one
        // orientation's error however long it lasts. Then the rest must not pin the heading.
        val times = samples.map { it.timestampNs * 1e-9 }
        val truth = samples.map { it.truth }
        val restTurn = Quaternion.fromAxisAngle(Vector3(0.0, 0.0, 1.0), 4.0 * PI / 180.0)
        fun table(name: String, swing: Double): Path {
            val file = dir.resolve(name)
            Files.newBufferedWriter(file).use { w ->
                w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
                for (s in samples) {
                    val t = s.timestampNs * 1e-9
                    val moving = rests.none { t in it }
                    val m = if (moving) s.mag * (1.0 + swing * kotlin.math.sin(2.0 * PI * t / 3.0)) else s.truth.inverseRotate(restTurn.rotate(s.truth.rotate(s.mag)))
                    val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, m.x, m.y, m.z)
                    w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it } + "\n")
                }
            }
            return file
        }
        val gated = OfflineSettings(headingSmoothing = 1.0)
        val trusting = gated.copy(smootherRestSpread = Double.POSITIVE_INFINITY)
        fun rms(file: Path, o: OfflineSettings) = headingRms(replay(file, o), times, truth, 0.0, 130.0)
        val swinging = table("swinging.csv", 0.08)
        val withGate = rms(swinging, gated)
        val withoutGate = rms(swinging, trusting)
        val msg = String.format(Locale.ROOT, "heading RMSE: rest trusted only for a consistent field %.2f°, always %.2f°", withGate, withoutGate)
        println(msg)
        assertTrue(withGate < 0.7 * withoutGate, msg)
        // The same rest error with a steady magnitude: the field is consistent, so the rest keeps its trust.
        val steady = table("steady.csv", 0.0)
        assertEquals(rms(steady, trusting), rms(steady, gated), 0.0)
    }

    @Test
    fun `one empty magnetometer cell or one non-finite gyroscope reading late in the recording leaves the smoother working before it`() {
        // In the last rest, where the smoother's backward filter starts: without care the bad value would stay in its
        // state from there back to the start, and every row before it would go unsmoothed.
        val row = 11_000
        val cases = mapOf(
            "an empty magnetometer cell" to restMotionRest("blank-mag.csv") { i, v -> if (i == row) v.take(6) + listOf("", "", "") else v },
            "a non-finite gyroscope reading" to restMotionRest("nan-gyro.csv") { i, v -> if (i == row) listOf("NaN", "NaN", "NaN") + v.drop(3) else v },
        )
        for ((what, file) in cases) {
            val (alone, _, without) = inMotion(file)
            val msg = String.format(Locale.ROOT, "%s: heading RMSE in motion, smoother alone %.2f°, without %.2f°", what, alone, without)
            println(msg)
            assertTrue(without > 2.0 && alone < 0.4 * without, msg)
        }
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

    @Test
    fun `with the magnetic trust a reading counts by the cube of the pass's trust`() {
        // A level device, still, whose field's heading is 20° off the smoother's: 10 s of readings at 100 Hz in
        // motion (the motion noise), once at full trust and once at half; at half each reading's variance is 8 ×.
        val o = OfflineSettings()
        val q = doubleArrayOf(1.0, 0.0, 0.0, 0.0)
        val m = doubleArrayOf(20.0 * kotlin.math.sin(20.0 * PI / 180.0), 20.0 * kotlin.math.cos(20.0 * PI / 180.0), -43.0)
        fun pulled(trust: Double): Double {
            val smoother = HeadingSmoother(o)
            val buf = java.nio.ByteBuffer.allocate(Spill.RECORD)
            for (i in 0 until 1000) smoother.filterStep(buf, 0, q, i > 0, 0.0, 0.0, 0.0, 0.01, true, m, false, false, trust)
            return kotlin.math.abs(deg(buf.getDouble(Spill.KX)))
        }
        val full = pulled(1.0)
        val half = pulled(0.5)
        val none = pulled(0.0)
        println(String.format(Locale.ROOT, "heading pulled in 10 s: %.2f° at full trust, %.2f° at half, %.2f° at none", full, half, none))
        assertTrue(full > 1.0, "at full trust the field pulls the heading: $full°")
        // The Kalman filter's gain with r × 8 on a random-walk state: the pull over the same time falls well below half.
        assertTrue(half < 0.45 * full, "half trust $half°, full $full°")
        assertEquals(0.0, none, 0.0)
    }
}
