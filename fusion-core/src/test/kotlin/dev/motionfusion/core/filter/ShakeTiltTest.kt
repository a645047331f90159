package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import dev.motionfusion.core.sim.ViolentMotion
import dev.motionfusion.core.sim.ViolentMotionKind
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.util.Locale
import kotlin.math.abs
import kotlin.math.acos

/**
 * Tilt through violent motion, not only after it: two 3-s shakes back to back (up to 20 rad/s about each axis,
 * 34 rad/s in all, near a ±2000°/s gyroscope's range; 4.5 g), an accelerometer clipping at ±8 g and a gyroscope
 * reading 3 % high. At the momentary quiet samples during the shaking (the accelerometer within 0.3 m/s² of g),
 * the inclination error's median stays within VQF 6D's on the same samples + 1°. The gyroscope's scale error over
 * the shakes' rotation dominates both; no filter that keeps the accelerometer out during the shake can do much
 * better. VQF's figure: `-Dshake.csv=FILE` writes the samples, `fusion-bench/python/vqf_sim_shake.py FILE` runs it.
 */
class ShakeTiltTest {
    private val samples: List<SimulatedSample> = MotionSimulator(
        SimulationSettings(
            seed = 1L, rateHz = 200.0, durationS = 12.0, restWindows = listOf(TimeWindow(0.0, 2.0)),
            violentMotions = listOf(ViolentMotion(ViolentMotionKind.SHAKE, 2.0), ViolentMotion(ViolentMotionKind.SHAKE, 5.0)),
            accRange = 8.0 * STANDARD_GRAVITY, gyroRange = 34.9, gyroScaleError = 0.03,
        ),
    ).run()

    private fun quiet(s: SimulatedSample): Boolean {
        val t = s.timestampNs * 1e-9
        return t in 2.0..8.0 && abs(s.acc.norm() - STANDARD_GRAVITY) < 0.3
    }

    private fun tiltDeg(a: Vector3, b: Vector3) = Math.toDegrees(acos((a.x * b.x + a.y * b.y + a.z * b.z).coerceIn(-1.0, 1.0)))

    private val zUp = Vector3(0.0, 0.0, 1.0)

    @Test
    fun `during shaking the inclination at momentary quiet samples stays within VQF's plus 1 degree`() {
        System.getProperty("shake.csv")?.let { path ->
            File(path).printWriter().use { w ->
                w.println("t_s,gx,gy,gz,ax,ay,az,quiet,qw,qx,qy,qz")
                for (s in samples) w.println(
                    listOf(s.timestampNs * 1e-9, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z).joinToString(",") +
                        ",${if (quiet(s)) 1 else 0},${s.truth.w},${s.truth.x},${s.truth.y},${s.truth.z}",
                )
            }
        }
        for (mode in listOf(FilterMode.IMU, FilterMode.MARG)) {
            val f = MadgwickFilter(FilterSettings(mode = mode))
            val errors = ArrayList<Double>()
            for (s in samples) {
                f.update(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x, s.mag.y, s.mag.z)
                if (quiet(s) && f.isInitialised) errors += tiltDeg(f.orientation().inverseRotate(zUp), s.truth.inverseRotate(zUp))
            }
            errors.sort()
            val median = errors[errors.size / 2]
            val msg = String.format(Locale.ROOT, "%s: %d quiet samples during the shakes, median inclination error %.2f° (VQF 6D %.2f°), largest %.2f°", mode, errors.size, median, VQF_6D_MEDIAN, errors.last())
            println(msg)
            assertTrue(errors.size >= 40, msg)
            assertTrue(median <= VQF_6D_MEDIAN + 1.0, msg)
        }
    }

    private companion object {
        /** VQF 6D (vqf 2.1.2, defaults) on the same samples, median over the same quiet samples, °. */
        const val VQF_6D_MEDIAN = 11.83
    }
}
