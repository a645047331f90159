package dev.motionfusion.app.live

import dev.motionfusion.core.AerospaceAngles
import dev.motionfusion.core.Orientations
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.RotationMatrix
import dev.motionfusion.core.sensormanager.androidOrientation
import dev.motionfusion.core.sensormanager.remapForDisplayRotation
import dev.motionfusion.app.settings.AngleConvention

/**
 * Three angles in degrees as shown: [yaw] (Android azimuth or aerospace yaw, 0..360),
 * [pitch] (−90..90) and [roll] (−180..180), in the [convention]'s signs.
 */
data class DisplayAngles(val yaw: Double, val pitch: Double, val roll: Double, val convention: AngleConvention)

/**
 * From a device → ENU orientation to what the live screen shows. Angles refer to the screen as
 * the user sees it: the rotation is first remapped for the display rotation
 * (Surface.ROTATION_0..270 = 0..3) as `SensorManager.remapCoordinateSystem` is used for it.
 */
object Readout {
    /** body (x nose = screen top, y right, z down) → screen frame (x right, y top, z out of the screen). */
    private val BODY_TO_SCREEN = RotationMatrix(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)

    /** ENU coordinates → NED coordinates. */
    private val ENU_TO_NED = RotationMatrix(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)

    /** The screen → ENU rotation of the device → ENU orientation [q] under [displayRotation]. */
    fun screenMatrix(q: Quaternion, displayRotation: Int): RotationMatrix =
        remapForDisplayRotation(q.normalized().toRotationMatrix(), displayRotation)

    /** The angles of [q] (device → ENU) for [displayRotation] in [convention]. */
    fun angles(q: Quaternion, displayRotation: Int, convention: AngleConvention): DisplayAngles =
        angles(screenMatrix(q, displayRotation), convention)

    /** The angles of the screen → ENU rotation [r] in [convention]. */
    fun angles(r: RotationMatrix, convention: AngleConvention): DisplayAngles = when (convention) {
        AngleConvention.ANDROID -> androidOrientation(r).let {
            DisplayAngles(wrap360(it.azimuthDeg), it.pitchDeg, it.rollDeg, convention)
        }
        AngleConvention.AEROSPACE -> AerospaceAngles.fromRotationMatrix(ENU_TO_NED * r * BODY_TO_SCREEN).let {
            DisplayAngles(wrap360(Math.toDegrees(it.yaw)), Math.toDegrees(it.pitch), Math.toDegrees(it.roll), convention)
        }
    }

    /**
     * Pitch (nose = screen top up, positive) and bank (right edge down, positive) in degrees for
     * the attitude indicator: the aerospace angles whatever the convention on screen.
     */
    fun attitude(q: Quaternion, displayRotation: Int): DisplayAngles = angles(q, displayRotation, AngleConvention.AEROSPACE)

    /** The angle of the rotation between two orientations, degrees, 0..180 (fusion-core's [Orientations.error], total). */
    fun angleBetweenDeg(a: Quaternion, b: Quaternion): Double = Math.toDegrees(Orientations.error(a.normalized(), b.normalized()).total)

    /**
     * The angle between the up directions of two orientations (device → world), degrees,
     * 0..180: their difference in tilt alone, blind to heading (meaningful in 6D, where the
     * heading is arbitrary); [Orientations.error]'s inclination.
     */
    fun tiltBetweenDeg(a: Quaternion, b: Quaternion): Double = Math.toDegrees(Orientations.error(a.normalized(), b.normalized()).inclination)

    /** [deg] in [0, 360): a tiny negative angle becomes 0, not a 360 rounded up from 360 − 1e-14. */
    fun wrap360(deg: Double): Double {
        val w = deg % 360.0
        val r = if (w < 0.0) w + 360.0 else w + 0.0
        return if (r >= 360.0) 0.0 else r
    }
}
