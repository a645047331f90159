package dev.motionfusion.core.filter

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test

/**
 * [MadgwickFilter.turnAround] (the offline estimate's backward pass starts from the forward pass's end): a held
 * reading keeps its age, so one that had gone stale before the turn (a magnetometer that stopped before the
 * gyroscope) is not taken as fresh by the pass that starts there.
 */
class TurnAroundTest {
    @Test
    fun `a reading stale at the turn stays stale, a fresh one stays fresh`() {
        val f = MadgwickFilter(FilterSettings())
        val ms = 1_000_000L
        // 100 Hz: all three for 1 s, then the gyroscope and the accelerometer alone for 2 s.
        for (i in 0..300) {
            val t = i * 10 * ms
            f.updateAccelerometer(t, 0.0, 0.0, 9.81)
            if (i <= 100) f.updateMagnetometer(t, 0.0, 22.0, -40.0)
            f.updateGyroscope(t, 0.0, 0.0, 0.01)
        }
        val before = f.diagnostics().staleSamples
        assertEquals(300L - 150L, before, "steps with the magnetometer older than maxGap (0.5 s)")
        // Backward: time runs as −t; the next step is 10 ms later on that clock.
        f.turnAround(-3_000L * ms)
        f.updateGyroscope(-2_990L * ms, 0.0, 0.0, -0.01)
        assertEquals(before + 1, f.diagnostics().staleSamples, "the magnetometer, 2 s old at the turn, is still stale after it")
        // The accelerometer, fresh at the turn, is fresh after it: with a fresh magnetometer the next step is not stale.
        f.updateMagnetometer(-2_985L * ms, 0.0, 22.0, -40.0)
        f.updateGyroscope(-2_980L * ms, 0.0, 0.0, -0.01)
        assertEquals(before + 1, f.diagnostics().staleSamples)
    }
}
