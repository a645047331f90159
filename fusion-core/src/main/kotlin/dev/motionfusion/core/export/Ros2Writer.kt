package dev.motionfusion.core.export

import dev.motionfusion.core.calib.yamlNumber
import dev.motionfusion.core.replay.ReplayStep
import java.io.BufferedOutputStream
import java.io.ByteArrayOutputStream
import java.io.OutputStream
import java.nio.charset.StandardCharsets

/**
 * A ROS 2 recording as one MCAP file (the MCAP format, unchunked and without a summary section:
 * readers scan it from the start), messages CDR-encoded (little-endian, XCDR1):
 *  - `imu/data_raw` sensor_msgs/msg/Imu: gyroscope and accelerometer, orientation not provided
 *    (orientation_covariance[0] = −1), as REP-145 says; the angular velocity and linear
 *    acceleration covariances from the [noise] model when one is known: the variance of one
 *    sample's white noise, σ² = N²·f (noise density N, the gyroscope's mean rate [rateHz] f), on the
 *    diagonal; unknown (zeros) without one;
 *  - `imu/data` sensor_msgs/msg/Imu: the same with the replay's orientation (sensor → ENU, as
 *    REP-103's world), its covariance unknown (zeros); from the filter's first orientation on;
 *  - `imu/mag` sensor_msgs/msg/MagneticField: each magnetometer reading at its own time, tesla.
 * frame_id [FRAME_ID] for all; header stamps and log times in the recording's own clock.
 */
internal class Ros2Writer(stream: OutputStream, private val hasMagnetometer: Boolean, about: About, noise: NoiseModel? = null, rateHz: Double = Double.NaN) : ExportWriter() {
    /** Per-sample white-noise variances (rad²/s², m²/s⁴); 0: unknown. */
    private val gyroscopeVariance = if (noise != null && rateHz.isFinite()) noise.gyroscopeNoiseDensity * noise.gyroscopeNoiseDensity * rateHz else 0.0
    private val accelerometerVariance = if (noise != null && rateHz.isFinite()) noise.accelerometerNoiseDensity * noise.accelerometerNoiseDensity * rateHz else 0.0
    private val out = BufferedOutputStream(stream, 1 shl 16)
    private val record = Bytes()
    private val cdr = Bytes()
    private val sequence = IntArray(4)

    init {
        out.write(MAGIC)
        write(OP_HEADER) { string("ros2"); string(about.source) }
        write(OP_SCHEMA) { u16(1); string("sensor_msgs/msg/Imu"); string("ros2msg"); bytes(IMU_DEFINITION.toByteArray(StandardCharsets.UTF_8)) }
        if (hasMagnetometer) write(OP_SCHEMA) { u16(2); string("sensor_msgs/msg/MagneticField"); string("ros2msg"); bytes(MAG_DEFINITION.toByteArray(StandardCharsets.UTF_8)) }
        val metadata = mapOf(
            "source" to about.source,
            "frame" to "frame_id $FRAME_ID: ${About.AXES}; orientation ${About.QUATERNION} (world: ${about.world}); stamps: ${About.TIME}",
            "covariance" to if (gyroscopeVariance > 0.0 || accelerometerVariance > 0.0) {
                "angular_velocity and linear_acceleration covariances: one sample's white-noise variance N^2 * f on the diagonal " +
                    "(gyroscope N = ${yamlNumber(noise!!.gyroscopeNoiseDensity)} rad/s/sqrt(Hz), accelerometer N = ${yamlNumber(noise.accelerometerNoiseDensity)} m/s^2/sqrt(Hz), " +
                    "f = ${yamlNumber(rateHz)} Hz, the gyroscope's mean rate); orientation and magnetic field covariances unknown (0)"
            } else {
                "unknown (0), no noise model given; orientation_covariance[0] = -1 on imu/data_raw (not provided)"
            },
        )
        channel(IMU_RAW, 1, "imu/data_raw", metadata)
        channel(IMU, 1, "imu/data", metadata)
        if (hasMagnetometer) channel(MAG, 2, "imu/mag", metadata)
    }

    private fun channel(id: Int, schema: Int, topic: String, metadata: Map<String, String>) = write(OP_CHANNEL) {
        u16(id); u16(schema); string(topic); string("cdr")
        val entries = Bytes()
        for ((k, v) in metadata) { entries.string(k); entries.string(v) }
        u32(entries.size.toLong()); raw(entries)
    }

    override fun step(step: ReplayStep) {
        if (step.specificForce[0].isNaN()) return
        counted(step.timestampNs)
        message(IMU_RAW, step.timestampNs) { imu(step, null) }
        if (step.initialised) {
            orientationRows++
            message(IMU, step.timestampNs) { imu(step, step.orientation) }
        }
    }

    override fun magnetometer(timestampNs: Long, values: DoubleArray) {
        if (!hasMagnetometer) return
        magnetometerRows++
        message(MAG, timestampNs) {
            header(timestampNs)
            align(8)
            for (k in 0 until 3) f64(values[k].toFloat().toDouble() * 1e-6)
            repeat(9) { f64(0.0) }
        }
    }

    /** sensor_msgs/msg/Imu; [q] [w, x, y, z] or null (not provided). */
    private fun Bytes.imu(step: ReplayStep, q: DoubleArray?) {
        header(step.timestampNs)
        align(8)
        if (q == null) repeat(4) { f64(0.0) } else { f64(q[1]); f64(q[2]); f64(q[3]); f64(q[0]) }
        f64(if (q == null) -1.0 else 0.0); repeat(8) { f64(0.0) }
        for (k in 0 until 3) f64(step.angularVelocity[k].toFloat().toDouble())
        for (k in 0 until 9) f64(if (k % 4 == 0) gyroscopeVariance else 0.0)
        for (k in 0 until 3) f64(step.specificForce[k].toFloat().toDouble())
        for (k in 0 until 9) f64(if (k % 4 == 0) accelerometerVariance else 0.0)
    }

    /** std_msgs/msg/Header at [ns]; the clock's ns split as builtin_interfaces/Time does (nanosec in 0 until 10⁹). */
    private fun Bytes.header(ns: Long) {
        u32(Math.floorDiv(ns, 1_000_000_000L)); u32(Math.floorMod(ns, 1_000_000_000L))
        val id = FRAME_ID.toByteArray(StandardCharsets.UTF_8)
        u32(id.size + 1L); raw(id); u8(0)
    }

    private inline fun message(channel: Int, ns: Long, body: Bytes.() -> Unit) {
        cdr.reset()
        cdr.u8(0); cdr.u8(1); cdr.u8(0); cdr.u8(0) // CDR_LE encapsulation
        cdr.origin = 4
        cdr.body()
        write(OP_MESSAGE) { u16(channel); u32((sequence[channel]++).toLong()); u64(ns); u64(ns); raw(cdr) }
    }

    private inline fun write(op: Int, content: Bytes.() -> Unit) {
        record.reset()
        record.content()
        out.write(op)
        val n = Bytes().apply { u64(record.size.toLong()) }
        out.write(n.array, 0, n.size)
        out.write(record.array, 0, record.size)
    }

    override fun close() {
        write(OP_DATA_END) { u32(0) }
        write(OP_FOOTER) { u64(0); u64(0); u32(0) }
        out.write(MAGIC)
        out.close()
    }

    /** A little-endian byte builder; [align] pads relative to [origin] (CDR: after the encapsulation). */
    internal class Bytes : ByteArrayOutputStream(256) {
        var origin = 0
        val array: ByteArray get() = buf

        fun u8(v: Int) = write(v)
        fun u16(v: Int) { write(v and 0xff); write((v shr 8) and 0xff) }
        fun u32(v: Long) { for (k in 0 until 4) write(((v shr (8 * k)) and 0xff).toInt()) }
        fun u64(v: Long) { for (k in 0 until 8) write(((v shr (8 * k)) and 0xff).toInt()) }
        fun f64(v: Double) { align(8); u64(java.lang.Double.doubleToRawLongBits(v)) }
        fun string(s: String) { val b = s.toByteArray(StandardCharsets.UTF_8); u32(b.size.toLong()); write(b, 0, b.size) }
        fun bytes(b: ByteArray) { u32(b.size.toLong()); write(b, 0, b.size) }
        fun raw(b: ByteArray) = write(b, 0, b.size)
        fun raw(b: Bytes) = write(b.buf, 0, b.size())
        val size: Int get() = count
        fun align(n: Int) { while ((count - origin) % n != 0) write(0) }
        override fun reset() { super.reset(); origin = 0 }
    }

    internal companion object {
        const val FRAME_ID = "imu_link"
        private val MAGIC = byteArrayOf(0x89.toByte(), 'M'.code.toByte(), 'C'.code.toByte(), 'A'.code.toByte(), 'P'.code.toByte(), '0'.code.toByte(), '\r'.code.toByte(), '\n'.code.toByte())
        private const val OP_HEADER = 0x01
        private const val OP_FOOTER = 0x02
        private const val OP_SCHEMA = 0x03
        private const val OP_CHANNEL = 0x04
        private const val OP_MESSAGE = 0x05
        private const val OP_DATA_END = 0x0F
        private const val IMU_RAW = 1
        private const val IMU = 2
        private const val MAG = 3

        private val SEPARATOR = "=".repeat(80)
        private val DEPENDENCIES = """
            |$SEPARATOR
            |MSG: std_msgs/Header
            |builtin_interfaces/Time stamp
            |string frame_id
            |$SEPARATOR
            |MSG: builtin_interfaces/Time
            |int32 sec
            |uint32 nanosec
            |$SEPARATOR
            |MSG: geometry_msgs/Vector3
            |float64 x
            |float64 y
            |float64 z
            |""".trimMargin()

        val IMU_DEFINITION = """
            |std_msgs/Header header
            |geometry_msgs/Quaternion orientation
            |float64[9] orientation_covariance
            |geometry_msgs/Vector3 angular_velocity
            |float64[9] angular_velocity_covariance
            |geometry_msgs/Vector3 linear_acceleration
            |float64[9] linear_acceleration_covariance
            |$SEPARATOR
            |MSG: geometry_msgs/Quaternion
            |float64 x
            |float64 y
            |float64 z
            |float64 w
            |""".trimMargin() + DEPENDENCIES

        val MAG_DEFINITION = """
            |std_msgs/Header header
            |geometry_msgs/Vector3 magnetic_field
            |float64[9] magnetic_field_covariance
            |""".trimMargin() + DEPENDENCIES
    }
}
