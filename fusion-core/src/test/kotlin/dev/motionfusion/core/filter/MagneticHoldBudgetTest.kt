package dev.motionfusion.core.filter

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * The hold limited in time (magRejectionFactor, magFirstFieldTime, magUndisturbedTime), on the detector alone:
 * readings of a given magnitude and dip every 10 ms. Each test also runs the detector with its setting off
 * and requires the other behaviour, so it fails when the mechanism is switched off.
 */
class MagneticHoldBudgetTest {
    private val dt = 0.01
    private val base = FilterSettings(magDisturbanceRejection = true, magMaxRejectionTime = 10.0)

    /** [steps] readings of [norm] µT; returns how many of them were used. */
    private fun MagneticDisturbanceDetector.feed(steps: Int, norm: Double, sinDip: Double = 0.87): Int =
        (0 until steps).count { accept(dt, norm, sinDip, sinDip) }

    @Test
    fun `with the budget spent a disturbed field is used at a reduced gain and the reference stays`() {
        val d = MagneticDisturbanceDetector(base.copy(magRejectionFactor = 2.0))
        assertEquals(100, d.feed(100, 48.0))
        // 15 s of a field 50 % stronger: held for the 10 s budget, then used at half the gain.
        assertEquals(0, d.feed(990, 72.0))
        assertEquals(0.0, d.gainFactor)
        val used = d.feed(510, 72.0)
        assertTrue(used in 495..500, "used $used of the last 510 readings")
        assertTrue(d.disturbed)
        assertEquals(0.5, d.gainFactor)
        // The reference is still the first field: it is undisturbed at once.
        assertEquals(300, d.feed(300, 48.0))
        assertFalse(d.disturbed)
        // 3 s undisturbed paid back 6 s: the next disturbance is held for about 6 s (10 − (10 − 6)) only.
        val held = (0 until 1000).takeWhile { !d.accept(dt, 72.0, 0.87, 0.87) }.size
        assertTrue(held in 590..610, "held for $held steps")

        // Without the budget the field of the moment becomes the reference after 10 s and the first one is then disturbed.
        val plain = MagneticDisturbanceDetector(base)
        plain.feed(100, 48.0)
        plain.feed(1100, 72.0)
        assertEquals(0, plain.feed(300, 48.0))
    }

    @Test
    fun `the first reference is a steady field, not the first reading`() {
        // The first 2 s in a disturbed field (about 60 µT), then 8 s of the room's steady 48 µT (less than
        // magMaxRejectionTime), then 60 µT again.
        fun usedAfter(settings: FilterSettings): Int {
            val d = MagneticDisturbanceDetector(settings)
            for (i in 0 until 200) d.accept(dt, 60.0 + (if (i % 2 == 0) 5.0 else -5.0) * (i % 7) / 7.0, 0.87, 0.87)
            d.feed(800, 48.0)
            return d.feed(300, 60.0)
        }
        assertEquals(0, usedAfter(base.copy(magFirstFieldTime = 5.0)), "the 48 µT field is the reference, 60 µT disturbed")
        assertEquals(300, usedAfter(base), "without it the first reading (about 60 µT) is the reference")
    }

    @Test
    fun `a disturbance ends only after the field has agreed for magUndisturbedTime`() {
        fun usedWhileFlickering(settings: FilterSettings): Int {
            val d = MagneticDisturbanceDetector(settings)
            d.feed(100, 48.0)
            // A field that returns to the reference for 0.3 s out of every 0.5 s (a magnet swinging past).
            return (0 until 900).count { i -> d.accept(dt, if (i % 50 < 20) 72.0 else 48.0, 0.87, 0.87) }
        }
        assertEquals(0, usedWhileFlickering(base.copy(magUndisturbedTime = 0.5)))
        assertEquals(540, usedWhileFlickering(base))
    }
}
