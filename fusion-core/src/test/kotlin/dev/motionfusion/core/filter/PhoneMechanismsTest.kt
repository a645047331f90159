package dev.motionfusion.core.filter

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.SimulatedRuns.headingDeg
import dev.motionfusion.core.filter.SimulatedRuns.inclinationDeg
import dev.motionfusion.core.filter.SimulatedRuns.index
import dev.motionfusion.core.filter.SimulatedRuns.max
import dev.motionfusion.core.filter.SimulatedRuns.rms
import dev.motionfusion.core.filter.SimulatedRuns.run
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * The mechanisms beyond the report added for phones, each isolated on simulated motion by switching
 * it off: the separate heading correction, the bias estimate during motion and its ramp after rest,
 * the fast heading convergence, the trust in a disturbed but steady field, the accelerometer low-passed
 * in a quasi-inertial frame, and the gyroscope saturation with inclination recovery.
 */
class PhoneMechanismsTest {
    /** Only the mechanism under test differs between the runs. */
    private val none = FilterSettings(
        headingGain = null, motionBiasGain = null, headingRecoveryTime = null, restBiasEstimation = false,
        accLowPassTime = null, inclinationRecoveryBeta = null,
    )

    @Test
    fun `a separate heading gain keeps a disturbed field out of inclination`() {
        val data = MotionSimulator(SimulationSettings(hardIron = Vector3(30.0, -20.0, 10.0), hardIronWindow = TimeWindow(20.0, 40.0))).run()
        val from = index(data, 20.0)
        val to = index(data, 40.0)
        val coupled = max(run(MadgwickFilter(none), data), data, from, to, ::inclinationDeg)
        val separate = max(run(MadgwickFilter(none.copy(headingGain = 0.05)), data), data, from, to, ::inclinationDeg)
        assertTrue(coupled > 2.0, "coupled inclination error $coupled°")
        assertTrue(separate < 1.0, "separate inclination error $separate°")
        // Undisturbed, heading still converges to the magnetometer's.
        val clean = MotionSimulator(SimulationSettings()).run()
        val est = run(MadgwickFilter(none.copy(headingGain = 0.05)), clean)
        assertTrue(rms(est, clean, index(clean, 30.0), metric = ::headingDeg) < 0.5)
    }

    @Test
    fun `the bias is learnt during motion from the heading error`() {
        // Never at rest, so the rest estimate cannot act; slow motion, as a phone held in the hand.
        val bias = Vector3(0.01, -0.008, 0.012)
        val data = MotionSimulator(SimulationSettings(durationS = 240.0, angularRate = 0.1, gyroBias = bias)).run()
        val settings = none.copy(headingGain = 0.05)
        val on = MadgwickFilter(settings.copy(motionBiasGain = 0.003))
        val estOn = run(on, data)
        val off = MadgwickFilter(settings)
        val estOff = run(off, data)
        assertEquals(Vector3.ZERO, off.diagnostics().gyroBias)
        // The heading error sees the bias along the vertical.
        val up = data.last().truth.inverseRotate(Vector3(0.0, 0.0, 1.0))
        val along = bias.dot(up)
        val left = kotlin.math.abs(on.diagnostics().gyroBias.dot(up) - along) / kotlin.math.abs(along)
        assertTrue(left < 0.3, "bias error left along the vertical: ${left * 100} % of $along rad/s")
        val from = index(data, 180.0)
        val hOn = rms(estOn, data, from, metric = ::headingDeg)
        val hOff = rms(estOff, data, from, metric = ::headingDeg)
        assertTrue(hOn < 0.5 * hOff, "heading error with $hOn°, without $hOff°")
    }

    @Test
    fun `after a rest estimate the motion estimate waits for motionBiasRestTime`() {
        // 8 s at rest, then motion through a disturbed field: those heading errors are not bias.
        val bias = Vector3(0.02, -0.01, 0.015)
        val data = MotionSimulator(
            SimulationSettings(
                gyroBias = bias, restWindows = listOf(TimeWindow(0.0, 8.0)),
                hardIron = Vector3(30.0, -20.0, 10.0), hardIronWindow = TimeWindow(20.0, 40.0),
            ),
        ).run()
        // β and heading gain as when this was measured, on the raw accelerometer, without the hard-iron estimate (which
        // would learn the disturbance fixed to the phone): the ramp is what differs.
        val settings = FilterSettings(motionBiasGain = 0.01, beta = 0.03, headingGain = 0.03, accLowPassTime = null, hardIronThreshold = null)
        fun biasError(s: FilterSettings) = MadgwickFilter(s).also { run(it, data) }.diagnostics().gyroBias.minus(bias).norm()
        val waiting = biasError(settings.copy(motionBiasRestTime = 1000.0))
        val atOnce = biasError(settings.copy(motionBiasRestTime = 0.0))
        assertTrue(waiting < 5e-4, "bias error waiting $waiting rad/s")
        assertTrue(atOnce > 3.0 * waiting, "bias error at once $atOnce rad/s, waiting $waiting rad/s")
    }

    @Test
    fun `the bias estimate stays within its limit`() {
        val data = MotionSimulator(SimulationSettings(durationS = 60.0, gyroBias = Vector3(0.0, 0.0, 0.2))).run()
        val f = MadgwickFilter(none.copy(headingGain = 0.05, motionBiasGain = 0.05, motionBiasLimit = 0.01))
        run(f, data)
        val b = f.diagnostics().gyroBias
        assertTrue(maxOf(kotlin.math.abs(b.x), kotlin.math.abs(b.y), kotlin.math.abs(b.z)) <= 0.01 + 1e-15, "bias $b")
    }

    @Test
    fun `a wrong first heading converges within seconds with the recovery time`() {
        // The first magnetometer readings carry a hard-iron offset: the filter starts with a wrong heading (an offset
        // that keeps the field below SensorRanges.MAX_EARTH_FIELD_UT, so the filter takes the reading).
        val data = MotionSimulator(SimulationSettings(hardIron = Vector3(60.0, 40.0, 0.0), hardIronWindow = TimeWindow(0.0, 0.05))).run()
        val settings = none.copy(headingGain = 0.05)
        val start = run(MadgwickFilter(settings), data.take(1)).single()
        val initial = headingDeg(start, data[0].truth)
        assertTrue(initial > 5.0, "initial heading error $initial°")
        val from = index(data, 3.0)
        val to = index(data, 6.0)
        val fast = max(run(MadgwickFilter(settings.copy(headingRecoveryTime = 10.0)), data), data, from, to, ::headingDeg)
        val slow = max(run(MadgwickFilter(settings), data), data, from, to, ::headingDeg)
        assertTrue(fast < 1.5, "with recovery $fast°")
        assertTrue(slow > 0.5 * initial, "without recovery $slow° (initially $initial°)")
    }

    @Test
    fun `a disturbed but steady field becomes the reference after magNewFieldTime`() {
        fun rejected(newFieldTime: Double?): List<Boolean> {
            val d = MagneticDisturbanceDetector(FilterSettings(magNewFieldTime = newFieldTime))
            val dt = 0.01
            // 10 s of a 48 µT field, then 30 s of a steady 60 µT field (another room), same dip.
            return (0 until 4000).map { i -> !d.accept(dt, if (i < 1000) 48.0 else 60.0, 0.87, 0.87) }
        }
        val trusting = rejected(5.0)
        val plain = rejected(null)
        assertFalse(trusting.subList(0, 1000).any { it })
        assertTrue(trusting.subList(1000, 1490).all { it }, "rejected until the field has been steady for 5 s")
        assertTrue(trusting.subList(1510, 4000).none { it }, "trusted after 5 s")
        assertTrue(plain.subList(1000, 4000).all { it }, "without it, rejected until magMaxRejectionTime (60 s)")
        // A field that keeps changing is not trusted.
        val d = MagneticDisturbanceDetector(FilterSettings(magNewFieldTime = 5.0))
        assertTrue((0 until 4000).map { i -> d.accept(0.01, if (i < 1000) 48.0 else if (i % 200 < 100) 60.0 else 75.0, 0.87, 0.87) }.subList(1000, 4000).none { it })
    }

    @Test
    fun `the accelerometer low-passed in a quasi-inertial frame keeps linear acceleration out of inclination`() {
        // 40 s of smooth world-frame linear acceleration (amplitude 1.5 g, 0.7–1.3 Hz) while the sensor turns at 1 rad/s.
        val data = MotionSimulator(SimulationSettings(linearAcceleration = 15.0, linearAccelerationWindow = TimeWindow(10.0, 50.0))).run()
        fun incl(s: FilterSettings) = rms(run(MadgwickFilter(s), data), data, index(data, 15.0), index(data, 50.0), ::inclinationDeg)
        for (beta in listOf(0.03, 0.1)) {
            val settings = none.copy(headingGain = 0.05, beta = beta)
            val raw = incl(settings)
            val lowPassed = incl(settings.copy(accLowPassTime = 3.0))
            assertTrue(raw > 2.0, "β $beta, raw accelerometer: $raw°")
            assertTrue(lowPassed < 0.5 * raw, "β $beta, low-passed: $lowPassed°, raw: $raw°")
        }
        val settings = none.copy(headingGain = 0.05)
        // Without linear acceleration, gravity passes the low-pass while the sensor turns (at up to 4 rad/s).
        val fast = MotionSimulator(SimulationSettings(angularRate = 4.0)).run()
        val calm = rms(run(MadgwickFilter(settings.copy(accLowPassTime = 3.0)), fast), fast, index(fast, 5.0), metric = ::inclinationDeg)
        assertTrue(calm < 0.5, "low-passed, no linear acceleration: $calm°")
    }

    @Test
    fun `after a saturated gyroscope reading inclination re-converges fast`() {
        // Eight readings clipped at the range (34 rad/s about x) where the sensor turned otherwise: the
        // integrated orientation is then off by about 80° in inclination, as after a clipped burst.
        val range = 34.0
        val clean = MotionSimulator(SimulationSettings(durationS = 30.0)).run()
        val burst = index(clean, 10.0)
        val data = clean.mapIndexed { i, s -> if (i in burst until burst + 8) s.copy(gyro = Vector3(range, 0.0, 0.0)) else s }
        fun worst(s: FilterSettings) = max(run(MadgwickFilter(s), data), data, index(data, 13.0), index(data, 15.0), ::inclinationDeg)
        val settings = FilterSettings(inclinationRecoveryBeta = 0.5, gyroSaturation = range)
        val f = MadgwickFilter(settings)
        run(f, data)
        assertEquals(8L, f.diagnostics().gyroscopeSaturations)
        val recovered = worst(settings)
        val notDetected = worst(settings.copy(gyroSaturation = null))
        val noRecovery = worst(settings.copy(inclinationRecoveryBeta = null))
        assertTrue(recovered < 2.0, "with detection and recovery $recovered°")
        assertTrue(notDetected > 10.0, "without detection $notDetected°")
        assertTrue(noRecovery > 10.0, "detection without recovery $noRecovery°")
        // The start is armed too: from an identity start (about 50° off) inclination converges within seconds.
        val identity = settings.copy(initialisation = Initialisation.IDENTITY)
        fun startWorst(s: FilterSettings) = max(run(MadgwickFilter(s), clean), clean, index(clean, 4.0), index(clean, 6.0), ::inclinationDeg)
        assertTrue(startWorst(identity) < 2.0, "identity start with recovery ${startWorst(identity)}°")
        assertTrue(startWorst(identity.copy(inclinationRecoveryBeta = null)) > 10.0, "identity start without recovery")
        // Once the start is over and without a saturated reading it does not act, even under linear acceleration.
        val plain = MotionSimulator(SimulationSettings(linearAcceleration = 10.0, linearAccelerationWindow = TimeWindow(5.0, 20.0))).run()
        val on = run(MadgwickFilter(settings), plain)
        val off = run(MadgwickFilter(settings.copy(inclinationRecoveryBeta = null)), plain)
        val from = index(plain, 5.0)
        assertTrue((from until plain.size).all { on[it].angleTo(off[it]) < 1e-3 }, "recovery acted without a saturated reading")
        // While the accelerometer is far from gravity it is not trusted: no recovery yet.
        val shaken = data.mapIndexed { i, s -> if (i in burst until burst + 1200) s.copy(acc = s.acc * 3.0) else s }
        val during = max(run(MadgwickFilter(settings), shaken), shaken, index(shaken, 13.0), index(shaken, 15.0), ::inclinationDeg)
        assertTrue(during > 10.0, "recovery acted on an untrusted accelerometer: $during°")
    }

    @Test
    fun `settings validate the new values`() {
        for (bad in listOf(-1.0, Double.NaN, Double.POSITIVE_INFINITY)) {
            assertTrue(runCatching { FilterSettings(headingGain = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(motionBiasGain = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(headingRecoveryTime = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(magNewFieldTime = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(motionBiasLimit = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(inclinationRecoveryBeta = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(accTrustTime = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(motionBiasRestTime = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(accLowPassTime = bad) }.isFailure)
            assertTrue(runCatching { FilterSettings(gyroSaturation = bad) }.isFailure)
        }
        assertTrue(runCatching { FilterSettings(motionBiasLimit = 0.0) }.isFailure)
        val r = FilterSettings.report()
        assertEquals(
            listOf(null, null, null, null, null, null, null),
            listOf(r.headingGain, r.motionBiasGain, r.headingRecoveryTime, r.magNewFieldTime, r.inclinationRecoveryBeta, r.accLowPassTime, r.gyroSaturation),
        )
    }
}
