package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale
import kotlin.math.PI
import kotlin.math.atan
import kotlin.math.sqrt
import kotlin.math.tan

/** The offline combination: heading and inclination weighted apart, disturbed fields, gaps in the recording. */
class OfflineCombinationTest {
    @TempDir
    lateinit var dir: Path

    private fun deg(r: Double) = r * 180.0 / PI

    private fun about(axis: Vector3, angleDeg: Double): DoubleArray =
        Quaternion.fromAxisAngle(axis, angleDeg * PI / 180.0).let { doubleArrayOf(it.w, it.x, it.y, it.z) }

    private fun q(a: DoubleArray) = Quaternion(a[0], a[1], a[2], a[3])

    @Test
    fun `heading and inclination are combined with their own weights`() {
        val base = about(Vector3(0.3, -0.5, 0.8).normalized(), 70.0)
        val cases = listOf(Vector3(0.0, 0.0, 1.0) to 0.2, Vector3(1.0, 0.0, 0.0) to 0.7, Vector3(0.0, 1.0, 0.0) to 0.7)
        for ((axis, w) in cases) {
            // The backward estimate: the forward one turned 10° about a world axis (vertical: heading; horizontal: inclination).
            val back = (q(about(axis, 10.0)) * q(base)).let { doubleArrayOf(it.w, it.x, it.y, it.z) }
            val p = base.copyOf()
            Blend.combine(p, back, 0.2, 0.7)
            val turned = q(p) * q(base).conjugate()
            val expected = deg(2.0 * atan(w * tan(5.0 * PI / 180.0)))
            assertEquals(expected, deg(turned.angleTo(Quaternion.IDENTITY)), 1e-9, "about $axis")
            val v = Vector3(turned.x, turned.y, turned.z).normalized()
            assertEquals(1.0, v.dot(axis), 1e-9, "still about $axis")
        }
        // Where one is missing, the other; equal weights are symmetric (for estimates a few degrees apart).
        fun nan() = doubleArrayOf(Double.NaN, Double.NaN, Double.NaN, Double.NaN)
        nan().let { Blend.combine(it, base, 0.0, 0.0); assertTrue(it.contentEquals(base)) }
        base.copyOf().let { Blend.combine(it, nan(), 1.0, 1.0); assertTrue(it.contentEquals(base)) }
        val other = (q(about(Vector3(1.0, 1.0, 1.0).normalized(), 4.0)) * q(base)).let { doubleArrayOf(it.w, it.x, it.y, it.z) }
        val a = base.copyOf().also { Blend.combine(it, other, 0.5, 0.5) }
        val b = other.copyOf().also { Blend.combine(it, base, 0.5, 0.5) }
        assertEquals(0.0, deg(q(a).angleTo(q(b))), 2e-3)
    }

    @Test
    fun `the pass that met a disturbed field lately gives way to the other`() {
        val ε = Blend.CONFIDENCE_FLOOR
        assertEquals((0.3 + ε) / (1.0 + 2 * ε), Blend.headingWeight(0.3, 0.0, 0.0), 1e-12)
        // The forward pass just came out of a disturbance, the backward one has not met it: the backward one gets
        // more, half even where it had none.
        assertTrue(Blend.headingWeight(0.3, 1.0, 0.0) > 0.85)
        assertEquals(0.5, Blend.headingWeight(0.0, 1.0, 0.0), 1e-12)
        assertTrue(Blend.headingWeight(0.0, 0.5, 0.0) > Blend.headingWeight(0.0, 0.2, 0.0))
        // The other way round, the forward one leads.
        assertTrue(Blend.headingWeight(0.5, 0.0, 1.0) < 0.1)
        // Both in it: the weights where neither was.
        assertEquals(0.5, Blend.headingWeight(0.3, 1.0, 1.0), 1e-12)
    }

    @Test
    fun `a reading is disturbed by its magnitude or dip against the recording's medians`() {
        val settings = FilterSettings()
        val field = FieldReference(settings)
        val level = doubleArrayOf(1.0, 0.0, 0.0, 0.0) // device frame = ENU
        // 50 µT dipping 60° below north, with a few disturbed readings among them.
        fun reading(norm: Double, dipDeg: Double) = doubleArrayOf(0.0, norm * kotlin.math.cos(dipDeg * PI / 180), -norm * kotlin.math.sin(dipDeg * PI / 180))
        repeat(1000) { field.add(reading(50.0 + (it % 7) * 0.3, 60.0 + (it % 5) * 0.5), level, rest = true) }
        repeat(300) { field.add(reading(90.0, 20.0), level, rest = true) }
        assertFalse(field.disturbed(reading(50.0, 60.0), level), "before the medians are fixed nothing is disturbed")
        field.settle()
        assertFalse(field.disturbed(reading(51.0, 61.0), level))
        assertTrue(field.disturbed(reading(51.0 * (1 + settings.magNormTolerance) + 1.0, 60.0), level), "magnitude")
        assertTrue(field.disturbed(reading(50.0, 60.0 + deg(settings.magDipTolerance) + 1.0), level), "dip")
        // The dip is taken in the orientation given: the same reading from a device turned 30° about east is disturbed.
        val tilted = about(Vector3(1.0, 0.0, 0.0), 30.0)
        assertTrue(field.disturbed(reading(50.0, 60.0), tilted))
        assertEquals(0.5 * kotlin.math.exp(-settings.headingGain!! * 2.0), field.decay(0.5, 2_000_000_000L), 1e-12)
    }

    @Test
    fun `the rest condition's spread is a positive number, infinity trusting every rest`() {
        for (bad in listOf(0.0, -0.01, Double.NaN)) {
            val e = org.junit.jupiter.api.assertThrows<IllegalArgumentException> { OfflineSettings(smootherRestSpread = bad) }
            assertTrue(e.message!!.contains("smootherRestSpread"), e.message)
        }
        assertEquals(Double.POSITIVE_INFINITY, OfflineSettings(smootherRestSpread = Double.POSITIVE_INFINITY).smootherRestSpread)
    }

    @Test
    fun `the spread of the field's magnitude counts the readings in motion only`() {
        val field = FieldReference(FilterSettings())
        val level = doubleArrayOf(1.0, 0.0, 0.0, 0.0)
        fun reading(norm: Double) = doubleArrayOf(0.0, norm * 0.5, -norm * kotlin.math.sqrt(0.75))
        // At rest anything: without a reading in motion the spread is 0.
        for (k in 0 until 2000) field.add(reading(10.0 + k * 0.05), level, rest = true)
        field.settle()
        assertEquals(0.0, field.motionSpread, "readings at rest only")
        // In motion a third each at 48, 50 and 52 µT: median 50, median absolute deviation 2 µT (in 0.1-µT bins: 20 of
        // them, the median in the bin from 50.0, whose middle is 50.05).
        for (k in 0 until 900) field.add(reading(48.05 + 2.0 * (k % 3)), level, rest = false)
        field.settle()
        assertEquals(1.4826 * 2.0 / 50.05, field.motionSpread, 1e-9)
    }

    /** Total error, °, RMS over the rows whose time is in [from, to) s; [orientations] in row order. */
    private fun rms(orientations: List<DoubleArray>, times: List<Double>, truth: List<Quaternion>, from: Double, to: Double): Double {
        val idx = times.indices.filter { times[it] >= from && times[it] < to }
        return sqrt(idx.sumOf { deg(q(orientations[it]).angleTo(truth[it])).let { e -> e * e } } / idx.size)
    }

    private fun replay(file: Path, offline: OfflineSettings?): List<DoubleArray> = Recording.open(file).use { rec ->
        val out = ArrayList<DoubleArray>()
        val listener = object : ReplayListener {
            override fun step(step: ReplayStep) {
                out += step.orientation.copyOf()
            }
        }
        rec.events().use { if (offline == null) Replayer().run(it, rec.originNs, listener) else Replayer().runOffline(it, rec.originNs, listener, offline = offline) }
        out
    }

    @Test
    fun `across a gap each pass goes on from the other's orientation, not from the one it carried over`() {
        // 10 s missing from a recording: the device turned meanwhile. (The causal filter, which carries its
        // orientation over the gap, has converged again by the end, where the backward pass starts from it.)
        val samples = MotionSimulator(SimulationSettings(durationS = 150.0, rateHz = 50.0, seed = 3)).run()
            .filter { it.timestampNs < 25_000_000_000L || it.timestampNs >= 35_000_000_000L }
        val file = dir.resolve("gap.csv")
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for (s in samples) {
                val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x, s.mag.y, s.mag.z)
                w.write(String.format(Locale.ROOT, "%.6f", s.timestampNs * 1e-9) + v.joinToString("") { "," + it } + "\n")
            }
        }
        val times = samples.map { it.timestampNs * 1e-9 }
        val truth = samples.map { it.truth }
        val causal = replay(file, null)
        assertEquals(samples.size, causal.size)
        val turned = deg(truth[times.indexOfFirst { it >= 35.0 }].angleTo(truth[times.indexOfLast { it < 25.0 }]))
        assertTrue(turned > 20.0, "the device turns by $turned° during the gap")
        // The causal filter settled before the gap; after it, it carries its orientation over and is far off.
        val settled = rms(causal, times, truth, 10.0, 25.0)
        assertTrue(rms(causal, times, truth, 35.0, 40.0) > settled + 5.0)
        for (weights in listOf(OfflineSettings(), OfflineSettings(1.0, 1.0), OfflineSettings(0.0, 0.0))) {
            val offline = replay(file, weights)
            // Just before the gap (where the backward pass arrives from beyond it) and just after (the second forward pass).
            for ((from, to) in listOf(20.0 to 25.0, 35.0 to 40.0)) {
                val o = rms(offline, times, truth, from, to)
                assertTrue(o < settled + 1.0, String.format(Locale.ROOT, "%s, %.0f–%.0f s: offline %.2f° against the settled causal %.2f°", weights, from, to, o, settled))
            }
        }
    }
}
