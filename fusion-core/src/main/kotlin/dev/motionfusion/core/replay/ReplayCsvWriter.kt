/*
 * The CSV written by `fusion replay`, one row per gyroscope sample:
 *
 *   t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg,yaw_deg,aero_pitch_deg,aero_roll_deg,
 *   lin_acc_east_m_s2,lin_acc_north_m_s2,lin_acc_up_m_s2
 *
 * q: sensor → ENU, Hamilton, scalar first (9 decimals). Android angles (degrees, 4 decimals) as
 * SensorManager.getOrientation of R(q), and aerospace angles (degrees, 4 decimals) of the phone as
 * an aircraft in North-East-Down: yaw = heading of the phone's top edge from magnetic north toward
 * east, pitch positive with the top edge up, roll positive with the right edge down; at pitch ±90°
 * roll is 0 (both from core's Orientations, where the definitions are). Linear acceleration in ENU, m/s²: R(q)·a − [0, 0, g₀] with the latest accelerometer
 * reading a and g₀ = 9.80665 (5 decimals). Rows before the filter is initialised have NaN.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.Orientations
import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.io.AsciiNumbers
import java.io.Closeable
import java.io.Flushable
import java.io.OutputStream

/** Writes replay steps as CSV to [out] (buffered; [close] closes [out] unless [closeStream] is false). */
public class ReplayCsvWriter(private val out: OutputStream, private val closeStream: Boolean = true) : ReplayListener, Closeable, Flushable {
    private val buf = ByteArray(1 shl 16)
    private var pos = 0
    private val angles = DoubleArray(9)

    /** Rows written. */
    public var rows: Long = 0L
        private set

    init {
        val h = (HEADER + "\n").toByteArray(Charsets.US_ASCII)
        h.copyInto(buf)
        pos = h.size
    }

    override fun step(step: ReplayStep) {
        if (pos + MAX_ROW > buf.size) drain()
        pos = AsciiNumbers.fixed(buf, pos, step.timeS, 9)
        val q = step.orientation
        for (k in 0 until 4) {
            buf[pos++] = COMMA
            pos = AsciiNumbers.fixed(buf, pos, q[k], 9)
        }
        derived(q, step.specificForce, angles)
        for (k in 0 until 6) {
            buf[pos++] = COMMA
            pos = AsciiNumbers.fixed(buf, pos, angles[k], 4)
        }
        for (k in 6 until 9) {
            buf[pos++] = COMMA
            pos = AsciiNumbers.fixed(buf, pos, angles[k], 5)
        }
        buf[pos++] = NL
        rows++
    }

    private fun drain() {
        out.write(buf, 0, pos)
        pos = 0
    }

    override fun flush() {
        drain()
        out.flush()
    }

    override fun close() {
        flush()
        if (closeStream) out.close()
    }

    public companion object {
        public const val HEADER: String = "t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg,yaw_deg,aero_pitch_deg,aero_roll_deg," +
            "lin_acc_east_m_s2,lin_acc_north_m_s2,lin_acc_up_m_s2"
        private const val COMMA = ','.code.toByte()
        private const val NL = '\n'.code.toByte()
        private const val MAX_ROW = 14 * 48
        private const val DEG = 180.0 / Math.PI

        /**
         * From the unit quaternion [q] (sensor → ENU) and the specific force [a] (device frame):
         * out[0..2] Android azimuth, pitch, roll; out[3..5] aerospace yaw, pitch, roll (degrees,
         * conventions in the file header); out[6..8] ENU linear acceleration (m/s²).
         */
        @JvmStatic
        public fun derived(q: DoubleArray, a: DoubleArray, out: DoubleArray) {
            val w = q[0]
            val x = q[1]
            val y = q[2]
            val z = q[3]
            Orientations.androidAndAerospaceAngles(q, out, 0)
            for (k in 0 until 6) out[k] *= DEG
            val r00 = 1 - 2 * (y * y + z * z)
            val r01 = 2 * (x * y - w * z)
            val r02 = 2 * (x * z + w * y)
            val r10 = 2 * (x * y + w * z)
            val r11 = 1 - 2 * (x * x + z * z)
            val r12 = 2 * (y * z - w * x)
            val r20 = 2 * (x * z - w * y)
            val r21 = 2 * (y * z + w * x)
            val r22 = 1 - 2 * (x * x + y * y)
            out[6] = r00 * a[0] + r01 * a[1] + r02 * a[2]
            out[7] = r10 * a[0] + r11 * a[1] + r12 * a[2]
            out[8] = r20 * a[0] + r21 * a[1] + r22 * a[2] - STANDARD_GRAVITY
        }
    }
}
