package dev.motionfusion.app.live

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.math.abs
import dev.motionfusion.app.settings.AngleConvention

/**
 * Angles of known orientations (device → ENU) in both conventions and for each display
 * rotation. Tolerance 1e-6°.
 */
class ReadoutTest {
    private val tol = 1e-6

    private fun about(axis: Vector3, deg: Double) = Quaternion.fromAxisAngle(axis, Math.toRadians(deg))
    private val flatNorth = Quaternion(1.0, 0.0, 0.0, 0.0)

    /** Top edge towards east: device y → east, a −90° turn about up. */
    private val topEast = about(Vector3.UNIT_Z, -90.0)

    /** Top edge raised by [deg] (rotation about the device x axis). */
    private fun topRaised(deg: Double) = about(Vector3.UNIT_X, deg)

    /** Right edge raised by [deg]. */
    private fun rightRaised(deg: Double) = about(Vector3.UNIT_Y, -deg)

    private fun assertAngles(yaw: Double, pitch: Double, roll: Double, a: DisplayAngles) {
        assertEquals(0.0, wrapped(yaw - a.yaw), tol, "yaw $a")
        assertEquals(pitch, a.pitch, tol, "pitch $a")
        assertEquals(0.0, wrapped(roll - a.roll), tol, "roll $a")
    }

    /** Difference folded into (−180, 180]. */
    private fun wrapped(d: Double): Double = ((d % 360.0) + 540.0) % 360.0 - 180.0

    @Test
    fun `flat with the top towards north is all zeros`() {
        for (c in AngleConvention.entries) assertAngles(0.0, 0.0, 0.0, Readout.angles(flatNorth, 0, c))
    }

    @Test
    fun `yawed 90 degrees reads 90 in both conventions`() {
        for (c in AngleConvention.entries) assertAngles(90.0, 0.0, 0.0, Readout.angles(topEast, 0, c))
    }

    @Test
    fun `pitch and roll signs of each convention`() {
        assertAngles(0.0, -30.0, 0.0, Readout.angles(topRaised(30.0), 0, AngleConvention.ANDROID))
        assertAngles(0.0, 30.0, 0.0, Readout.angles(topRaised(30.0), 0, AngleConvention.AEROSPACE))
        // Both rolls are positive with the right edge down (getOrientation's roll = atan2(−A_x, A_z)).
        assertAngles(0.0, 0.0, -20.0, Readout.angles(rightRaised(20.0), 0, AngleConvention.ANDROID))
        assertAngles(0.0, 0.0, -20.0, Readout.angles(rightRaised(20.0), 0, AngleConvention.AEROSPACE))
        assertAngles(0.0, 0.0, 20.0, Readout.angles(rightRaised(-20.0), 0, AngleConvention.ANDROID))
    }

    @Test
    fun `upright phone is pitched 90 degrees`() {
        assertEquals(-90.0, Readout.angles(topRaised(90.0), 0, AngleConvention.ANDROID).pitch, tol)
        assertEquals(90.0, Readout.angles(topRaised(90.0), 0, AngleConvention.AEROSPACE).pitch, tol)
    }

    @Test
    fun `upside down reads roll 180`() {
        val q = about(Vector3.UNIT_Y, 180.0)
        for (c in AngleConvention.entries) assertAngles(0.0, 0.0, 180.0, Readout.angles(q, 0, c))
    }

    @Test
    fun `each display rotation turns the heading of the screen's top edge`() {
        // Flat, device top north: with the display turned, the screen's up is another device edge.
        assertAngles(0.0, 0.0, 0.0, Readout.angles(flatNorth, 0, AngleConvention.ANDROID))
        assertAngles(90.0, 0.0, 0.0, Readout.angles(flatNorth, 1, AngleConvention.ANDROID))
        assertAngles(180.0, 0.0, 0.0, Readout.angles(flatNorth, 2, AngleConvention.ANDROID))
        assertAngles(270.0, 0.0, 0.0, Readout.angles(flatNorth, 3, AngleConvention.ANDROID))
    }

    @Test
    fun `in landscape raising the device top is a roll of the screen`() {
        // ROTATION_90: screen up = device +x, screen right = device −y. Raising the device top
        // raises the screen's left edge: Android roll +30 (right edge down), pitch 0.
        assertAngles(0.0, 0.0, 30.0, Readout.angles(topRaised(30.0), 1, AngleConvention.ANDROID).copy(yaw = 0.0))
        // ROTATION_270: screen up = device −x: the device top is the screen's right edge.
        assertAngles(0.0, 0.0, -30.0, Readout.angles(topRaised(30.0), 3, AngleConvention.ANDROID).copy(yaw = 0.0))
        // ROTATION_180: the device top is the screen's bottom: raising it tilts the screen's top down.
        assertAngles(180.0, 30.0, 0.0, Readout.angles(topRaised(30.0), 2, AngleConvention.ANDROID))
    }

    @Test
    fun `angle between orientations and between their tilts`() {
        val a = topRaised(10.0)
        val b = about(Vector3.UNIT_Z, 25.0) * a // same tilt, heading turned by 25°
        assertEquals(25.0, Readout.angleBetweenDeg(a, b), 1e-9)
        assertEquals(0.0, Readout.tiltBetweenDeg(a, b), 1e-6)
        val c = topRaised(-5.0)
        assertEquals(15.0, Readout.angleBetweenDeg(a, c), 1e-9)
        assertEquals(15.0, Readout.tiltBetweenDeg(a, c), 1e-9)
        // q and −q are the same orientation.
        assertEquals(0.0, Readout.angleBetweenDeg(a, -a), 1e-9)
        assertEquals(180.0, Readout.angleBetweenDeg(flatNorth, about(Vector3.UNIT_X, 180.0)), 1e-9)
    }

    @Test
    fun `headings wrap into 0 to 360 and round without 360`() {
        assertEquals(350.0, Readout.wrap360(-10.0), 1e-12)
        assertEquals(0.0, Readout.wrap360(720.0), 1e-12)
        assertEquals(0.0, Readout.wrap360(-1e-14), 0.0)
        assertEquals(0.0, displayHeading(359.96))
        assertEquals(0.0, displayDegrees(-0.04))
        assertEquals(1.0, abs(displayDegrees(-1.0)))
    }
}
