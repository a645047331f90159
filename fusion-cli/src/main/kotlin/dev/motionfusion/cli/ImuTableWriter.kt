package dev.motionfusion.cli

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.io.AsciiNumbers
import java.io.BufferedOutputStream
import java.io.Closeable
import java.io.OutputStream
import java.util.zip.GZIPOutputStream

/**
 * Writes an IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (the layout ImuTableReader reads: s,
 * rad/s, m/s², µT; t_s to 1 ns, readings as the shortest decimal of their float value, NaN where
 * unknown), gzip-compressed when [gzip]. Closes [file].
 */
internal class ImuTableWriter(file: OutputStream, gzip: Boolean, private val magnetometer: Boolean) : Closeable {
    private val stream: OutputStream = BufferedOutputStream(file, 1 shl 16).let { if (gzip) GZIPOutputStream(it, 1 shl 16) else it }
    private val buf = ByteArray(512)

    /** Rows written. */
    var rows = 0L
        private set

    init {
        stream.write((if (magnetometer) "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" else "t_s,gx,gy,gz,ax,ay,az\n").toByteArray())
    }

    /** One row; [mag] is ignored without magnetometer columns. */
    fun row(timeS: Double, gyro: DoubleArray, acc: DoubleArray, mag: DoubleArray) {
        rows++
        var p = AsciiNumbers.fixed(buf, 0, timeS, 9)
        for (v in if (magnetometer) arrayOf(gyro, acc, mag) else arrayOf(gyro, acc)) {
            for (k in 0 until 3) {
                buf[p++] = ','.code.toByte()
                p = AsciiNumbers.float(buf, p, v[k].toFloat())
            }
        }
        buf[p++] = '\n'.code.toByte()
        stream.write(buf, 0, p)
    }

    private val g = DoubleArray(3)
    private val a = DoubleArray(3)
    private val m = DoubleArray(3)

    fun row(timeS: Double, gyro: Vector3, acc: Vector3, mag: Vector3) {
        for (k in 0 until 3) { g[k] = gyro[k]; a[k] = acc[k]; m[k] = mag[k] }
        row(timeS, g, a, m)
    }

    override fun close() = stream.close()
}
