package dev.motionfusion.core.filter

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.SimulatedRuns.headingDeg
import dev.motionfusion.core.filter.SimulatedRuns.inclinationDeg
import dev.motionfusion.core.filter.SimulatedRuns.index
import dev.motionfusion.core.filter.SimulatedRuns.max
import dev.motionfusion.core.filter.SimulatedRuns.rms
import dev.motionfusion.core.filter.SimulatedRuns.run
import dev.motionfusion.core.filter.SimulatedRuns.totalDeg
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** Behaviour on simulated motion with known truth; each addition to the report isolated by switching it off. */
class FilterBehaviourTest {
    /** 60 s of motion after 8 s at rest, with a gyroscope bias. */
    private val base = SimulationSettings(durationS = 60.0, gyroBias = Vector3(0.02, -0.01, 0.015), restWindows = listOf(TimeWindow(0.0, 8.0)))
    private val data = MotionSimulator(base).run()
    private val after30 = index(data, 30.0)

    @Test
    fun `starts at the orientation of the first accelerometer and magnetometer sample`() {
        val est = run(MadgwickFilter(), data.take(1))
        assertTrue(totalDeg(est[0], data[0].truth) < 1.0, "initial error ${totalDeg(est[0], data[0].truth)}°")
    }

    @Test
    fun `converges from the identity and reaches a small steady-state error`() {
        val est = run(MadgwickFilter(FilterSettings(initialisation = Initialisation.IDENTITY, beta = 0.1, headingGain = null)), data)
        assertTrue(totalDeg(est[0], data[0].truth) > 50.0)
        val converged = est.indices.first { i -> (i until minOf(i + 200, est.size)).all { totalDeg(est[it], data[it].truth) < 2.0 } }
        val seconds = data[converged].timestampNs * 1e-9
        assertTrue(seconds < 10.0, "converged after $seconds s")
        val steady = rms(est, data, after30, metric = ::totalDeg)
        assertTrue(steady < 0.5, "steady-state RMS $steady°")
    }

    @Test
    fun `defaults reach a steady-state error below half a degree`() {
        val est = run(MadgwickFilter(), data)
        val steady = rms(est, data, after30, metric = ::totalDeg)
        assertTrue(steady < 0.5, "steady-state RMS $steady°")
    }

    @Test
    fun `rest detection estimates the gyroscope bias and that reduces the error`() {
        val on = MadgwickFilter(FilterSettings(motionBiasGain = null))
        val estOn = run(on, data)
        val biasError = (on.diagnostics().gyroBias - base.gyroBias).norm()
        assertTrue(biasError < 3e-4, "bias error $biasError rad/s")
        val off = MadgwickFilter(FilterSettings(restBiasEstimation = false, motionBiasGain = null))
        val estOff = run(off, data)
        assertEquals(Vector3.ZERO, off.diagnostics().gyroBias)
        val errOn = rms(estOn, data, after30, metric = ::totalDeg)
        val errOff = rms(estOff, data, after30, metric = ::totalDeg)
        assertTrue(errOff > 3.0 * errOn, "with $errOn°, without $errOff°")
    }

    @Test
    fun `rest is flagged at rest and not in motion`() {
        // The simulated bias (1.55°/s) is beyond restMaxRate: rest is declared after restImplausibleTime (5 s), not restMinTime.
        val filter = MadgwickFilter()
        val flags = data.map { s -> filter.update(s.timestampNs, s.gyro, s.acc, s.mag); filter.diagnostics().atRest }
        assertTrue((index(data, 5.5) until index(data, 7.9)).all { flags[it] }, "rest not flagged in 5.5..7.9 s")
        assertTrue((index(data, 10.0) until data.size).none { flags[it] }, "rest flagged in motion")
        // A bias within restMaxRate: rest from restMinTime (1.5 s).
        val small = MotionSimulator(base.copy(gyroBias = Vector3(0.005, -0.004, 0.006))).run()
        val f2 = MadgwickFilter()
        val flags2 = small.map { s -> f2.update(s.timestampNs, s.gyro, s.acc, s.mag); f2.diagnostics().atRest }
        assertTrue((index(small, 2.0) until index(small, 7.9)).all { flags2[it] }, "rest not flagged in 2..7.9 s with a small bias")
    }

    @Test
    fun `a slow steady turn is not taken as a rest and its rate not as the bias`() {
        // Flat, turning about the vertical at 1.7°/s with no bias: within restGyroThreshold (3°/s) and the accelerometer
        // steady, so without the plausibility check it was a rest after 1.5 s and the turn became the bias.
        val filter = MadgwickFilter()
        val rate = 0.03
        var t = 0L
        fun turn(seconds: Double) {
            repeat((seconds * 100).toInt()) {
                t += 10_000_000L
                filter.update(t, 0.0, 0.0, rate, 0.0, 0.0, 9.81)
            }
        }
        turn(4.5)
        assertFalse(filter.diagnostics().atRest, "a 1.7°/s turn flagged as rest within 4.5 s")
        assertTrue(filter.diagnostics().gyroBias.norm() < 1e-3, "bias ${filter.diagnostics().gyroBias} rad/s from a slow turn")
        // Held for restImplausibleTime it is a rest: a bias that large (an uncalibrated gyroscope) is still estimated.
        turn(2.0)
        assertTrue(filter.diagnostics().atRest, "rest not flagged after 6.5 s")
        assertEquals(rate, filter.diagnostics().gyroBias.z, 1e-3)
    }

    @Test
    fun `a rest that ends as it is declared takes the mean of its readings, not its last one`() {
        // A noisy gyroscope (each reading 0.02 rad/s from the bias on every axis, within restGyroThreshold), still
        // until rest is declared, then moving: a walker who stops for two seconds. The bias it leaves is what the
        // rest of the recording runs on; one reading as the bias would be 1.1°/s off on each axis.
        val bias = doubleArrayOf(0.004, -0.003, 0.005)
        val filter = MadgwickFilter()
        var t = 0L
        var k = 0
        while (!filter.diagnostics().atRest) {
            assertTrue(k < 1000, "no rest within 10 s")
            val s = if (k % 2 == 0) 0.02 else -0.02
            t += 10_000_000L
            filter.update(t, bias[0] + s, bias[1] - s, bias[2] + s, 0.0, 0.0, 9.81)
            k++
        }
        t += 10_000_000L
        filter.update(t, 1.0, 0.0, 0.0, 0.0, 0.0, 9.81)
        assertFalse(filter.diagnostics().atRest)
        val b = filter.diagnostics().gyroBias
        for ((axis, v) in listOf(b.x, b.y, b.z).withIndex()) assertEquals(bias[axis], v, 1e-3, "bias axis $axis")
    }

    @Test
    fun `a slow turn that stops before a rest is no part of the rest's bias`() {
        // Flat, turning at 2.3°/s (within restGyroThreshold, beyond restMaxRate) for 2.5 s, then still with a bias of
        // 0.001 rad/s: the rest is declared once the low-passed rate has been within restMaxRate for restMinTime, and
        // its bias is the mean of that stretch, not of the turn before it (which would be 0.023 rad/s).
        val filter = MadgwickFilter()
        var t = 0L
        fun step(rate: Double) {
            t += 10_000_000L
            filter.update(t, 0.0, 0.0, rate, 0.0, 0.0, 9.81)
        }
        repeat(250) { step(0.04) }
        var k = 0
        while (!filter.diagnostics().atRest) {
            assertTrue(k++ < 400, "no rest within 4 s of the stop")
            step(0.001)
        }
        assertEquals(0.001, filter.diagnostics().gyroBias.z, 2e-4)
    }

    @Test
    fun `the gyroscope holds heading through a magnetic disturbance`() {
        val disturbed = MotionSimulator(base.copy(hardIron = Vector3(30.0, -20.0, 10.0), hardIronWindow = TimeWindow(20.0, 40.0))).run()
        val from = index(disturbed, 20.0)
        val to = index(disturbed, 45.0)
        // The report's coupled MARG step, so that only the rejection differs (the disturbance is fixed to the phone,
        // which the hard-iron estimate would learn: HardIronEstimateTest).
        val settings = FilterSettings(headingGain = null, motionBiasGain = null, headingRecoveryTime = null, magDisturbanceRejection = true, hardIronThreshold = null)
        val filter = MadgwickFilter(settings)
        val flags = ArrayList<Boolean>()
        val est = disturbed.map { s -> filter.update(s.timestampNs, s.gyro, s.acc, s.mag); flags.add(filter.diagnostics().magneticDisturbance); filter.orientation() }
        val withDetection = max(est, disturbed, from, to, ::headingDeg)
        val without = max(run(MadgwickFilter(settings.copy(magDisturbanceRejection = false)), disturbed), disturbed, from, to, ::headingDeg)
        assertTrue(withDetection < 1.0, "heading error with detection $withDetection°")
        assertTrue(without > 10.0, "heading error without detection $without°")
        assertTrue((0 until from).none { flags[it] }, "disturbance flagged before it began")
        assertTrue(flags.subList(from, index(disturbed, 40.0)).count { it } > 0.9 * (index(disturbed, 40.0) - from))
        assertFalse(flags.last())
    }

    @Test
    fun `accelerometer rejection protects inclination during linear acceleration`() {
        val accelerating = MotionSimulator(base.copy(linearAcceleration = 4.0, linearAccelerationWindow = TimeWindow(20.0, 24.0))).run()
        val from = index(accelerating, 20.0)
        val to = index(accelerating, 26.0)
        // On the raw accelerometer (the low-pass, on by default, is the other answer to linear acceleration).
        val settings = FilterSettings(mode = FilterMode.IMU, beta = 0.1, accLowPassTime = null)
        val filter = MadgwickFilter(settings.copy(accRejection = true))
        val est = run(filter, accelerating, useMag = false)
        val with = max(est, accelerating, from, to, ::inclinationDeg)
        val without = max(run(MadgwickFilter(settings), accelerating, useMag = false), accelerating, from, to, ::inclinationDeg)
        assertTrue(with < 1.5, "inclination error with rejection $with°")
        assertTrue(without > 2.5, "inclination error without rejection $without°")
        assertTrue(filter.diagnostics().accelerometerRejections > 0)
        // In MARG mode the magnetometer keeps correcting heading while the accelerometer is out
        // (uncorrected gyroscope bias, so heading would drift without it).
        val marg = run(MadgwickFilter(FilterSettings(accRejection = true, restBiasEstimation = false, beta = 0.1)), accelerating)
        val heading = max(marg, accelerating, from, to, ::headingDeg)
        val plain = max(run(MadgwickFilter(FilterSettings(restBiasEstimation = false, beta = 0.1)), accelerating), accelerating, from, to, ::headingDeg)
        assertTrue(heading < 2.0 * plain, "heading error in MARG mode with rejection $heading°, without $plain°")
    }

    @Test
    fun `accelerometer rejection recovers from a wrong estimate`() {
        // Identity start: every reading disagrees with the estimate; rejection must not last for ever.
        val est = run(MadgwickFilter(FilterSettings(initialisation = Initialisation.IDENTITY, accRejection = true, beta = 0.1, headingGain = null)), data)
        assertTrue(rms(est, data, after30, metric = ::totalDeg) < 0.5)
    }

    @Test
    fun `a field stronger than any earth field is left out as a raw magnetometer's would be`() {
        // A raw magnetometer: the simulated field plus a hard-iron offset of 800 µT (as ADVIO's iPhone reads, ~630 µT).
        val raw = MadgwickFilter()
        val none = MadgwickFilter()
        data.forEach { s ->
            raw.update(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x + 300.0, s.mag.y + 400.0, s.mag.z - 600.0)
            none.update(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z)
            assertEquals(none.orientation(), raw.orientation(), "at ${s.timestampNs} ns: the raw field must not enter")
        }
        val d = raw.diagnostics()
        assertTrue(d.magneticDisturbance, "shown as disturbed")
        assertEquals(d.gyroscopeSteps, d.magneticRejections, "every step counts its refused reading")
    }

    @Test
    fun `a strong field within the limit still enters`() {
        // 150 µT: what a calibrated phone reads near steel for a moment; the filter's own mechanisms decide.
        val strong = MadgwickFilter()
        val none = MadgwickFilter()
        val scale = 150.0 / data[0].mag.norm()
        val est = data.map { s ->
            strong.update(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, s.mag.x * scale, s.mag.y * scale, s.mag.z * scale)
            none.update(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z)
            strong.orientation()
        }
        assertEquals(0L, strong.diagnostics().magneticRejections)
        assertTrue(rms(est, data, after30, metric = ::headingDeg) < 1.0, "the scaled field still gives the heading")
    }

    @Test
    fun `sensors delivered separately at different rates`() {
        // Gyroscope 200 Hz, accelerometer 100 Hz, magnetometer 50 Hz, each with its own timestamps.
        val filter = MadgwickFilter()
        val est = data.mapIndexed { i, s ->
            if (i % 2 == 0) filter.updateAccelerometer(s.timestampNs - 1_000_000, s.acc.x, s.acc.y, s.acc.z)
            if (i % 4 == 0) filter.updateMagnetometer(s.timestampNs - 2_000_000, s.mag.x, s.mag.y, s.mag.z)
            filter.updateGyroscope(s.timestampNs, s.gyro.x, s.gyro.y, s.gyro.z)
            filter.orientation()
        }
        assertTrue(rms(est, data, after30, metric = ::totalDeg) < 0.6)
        assertEquals(0L, filter.diagnostics().staleSamples)
    }

    @Test
    fun `timestamp jitter and dropped samples are integrated over the real intervals`() {
        val rough = MotionSimulator(base.copy(timestampJitter = 0.001, dropProbability = 0.05)).run()
        val est = run(MadgwickFilter(), rough)
        assertTrue(rms(est, rough, index(rough, 30.0), metric = ::totalDeg) < 0.7)
    }

    @Test
    fun `the report's zeta estimates a gyroscope bias in MARG steps`() {
        val settings = FilterSettings(restBiasEstimation = false, zeta = 0.01, headingGain = null, motionBiasGain = null)
        val filter = MadgwickFilter(settings)
        run(filter, MotionSimulator(base.copy(durationS = 120.0)).run())
        val error = (filter.diagnostics().gyroBias - base.gyroBias).norm()
        assertTrue(error < 0.5 * base.gyroBias.norm(), "ζ bias error $error rad/s")
    }
}
