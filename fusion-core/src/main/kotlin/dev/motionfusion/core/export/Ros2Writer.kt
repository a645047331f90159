package dev.motionfusion.core.export

import dev.motionfusion.core.calib.yamlNumber
import dev.motionfusion.core.replay.ReplayStep
import java.io.BufferedOutputStream
import java.io.ByteArrayOutputStream
import java.io.OutputStream
import java.nio.charset.StandardCharsets
import java.util.zip.CRC32

/**
 * A ROS 2 recording as one MCAP file, chunked and indexed as rosbag2's own MCAP files are, so that
 * `ros2 bag play` (which reads in receive-time order through the index) and viewers
 * that refuse unindexed files open it, messages CDR-encoded (little-endian, XCDR1):
 *  - `/imu/data_raw` sensor_msgs/msg/Imu: gyroscope and accelerometer, orientation not provided
 *    (orientation_covariance[0] = −1), as REP-145 says; the angular velocity and linear
 *    acceleration covariances from the [noise] model when one is known: the variance of one
 *    sample's white noise, σ² = N²·f (noise density N, the gyroscope's rate [rateHz] f, gaps left out), on the
 *    diagonal; unknown (zeros) without one;
 *  - `/imu/data` sensor_msgs/msg/Imu: the same with the replay's orientation (sensor → ENU, as
 *    REP-103's world), its covariance unknown (zeros); from the filter's first orientation on;
 *  - `/imu/mag` sensor_msgs/msg/MagneticField: each magnetometer reading at its own time, tesla.
 * Topic names are fully qualified, as rosbag2 records them (`ros2 bag play --topics` matches them
 * exactly). frame_id [FRAME_ID] for all; header stamps and log times in the recording's own clock (as Exports writes it: never negative).
 *
 * Layout: magic, Header (profile `ros2`), the Schema and Channel records, then the messages in
 * uncompressed Chunks of about [CHUNK_BYTES] of records each, every Chunk followed by one Message
 * Index per channel in it (log time, offset into the chunk's records); Data End (with the CRC-32 of
 * everything before it); the Summary: Schemas and Channels again, Statistics (counts, first and last
 * log time, messages per channel), one Chunk Index per chunk; one Summary Offset per group; Footer
 * (summary start, summary offset start, CRC-32 of the summary through the footer's offsets); magic.
 * Streaming: only the chunk being filled is held, and of the others their index entries.
 *
 * Each channel's metadata holds `offered_qos_profiles` (required by the MCAP `ros2` profile; rosbag2
 * replays with it): one profile, ROS 2's sensor-data profile (rmw_qos_profile_sensor_data) as a
 * sensor driver offers it — history keep last (1), depth 5, reliability best effort (2), durability
 * volatile (2), deadline, lifespan and liveliness lease duration unspecified (0 s, 0 ns), liveliness
 * system default (0), avoid_ros_namespace_conventions false — as a YAML list with rosbag2's keys and
 * rmw's enum numbers (the numeric form every rosbag2 release reads; newer ones also write names).
 */
internal class Ros2Writer(stream: OutputStream, private val hasMagnetometer: Boolean, about: About, noise: NoiseModel? = null, rateHz: Double = Double.NaN) : ExportWriter() {
    /** Per-sample white-noise variances (rad²/s², m²/s⁴); 0: unknown. */
    private val gyroscopeVariance = if (noise != null && rateHz.isFinite()) noise.gyroscopeNoiseDensity * noise.gyroscopeNoiseDensity * rateHz else 0.0
    private val accelerometerVariance = if (noise != null && rateHz.isFinite()) noise.accelerometerNoiseDensity * noise.accelerometerNoiseDensity * rateHz else 0.0
    private val out = Sink(stream)
    private val record = Bytes()
    private val cdr = Bytes()
    private val sequence = IntArray(CHANNELS + 1)

    /** Schema and Channel records as written (opcode, length, content), repeated in the summary. */
    private val schemas = ArrayList<ByteArray>()
    private val channels = ArrayList<ByteArray>()

    /** The chunk being filled: its records, per channel its message index entries (log time, offset), its log time range. */
    private val chunk = Bytes(CHUNK_BYTES + (CHUNK_BYTES shr 4))
    private val index = Array(CHANNELS + 1) { Bytes() }
    private var chunkMessages = 0
    private var chunkStart = 0L
    private var chunkEnd = 0L

    /** The closed chunks' index entries and the statistics. */
    private val chunks = ArrayList<ChunkEntry>()
    private val channelMessages = LongArray(CHANNELS + 1)
    private var messages = 0L
    private var firstLogTime = 0L
    private var lastLogTime = 0L

    init {
        out.write(MAGIC)
        write(out, OP_HEADER) { string("ros2"); string(about.source) }
        schemas += recordBytes(OP_SCHEMA) { u16(1); string("sensor_msgs/msg/Imu"); string("ros2msg"); bytes(IMU_DEFINITION.toByteArray(StandardCharsets.UTF_8)) }
        if (hasMagnetometer) schemas += recordBytes(OP_SCHEMA) { u16(2); string("sensor_msgs/msg/MagneticField"); string("ros2msg"); bytes(MAG_DEFINITION.toByteArray(StandardCharsets.UTF_8)) }
        val metadata = mapOf(
            "offered_qos_profiles" to OFFERED_QOS_PROFILES,
            "source" to about.source,
            "frame" to "frame_id $FRAME_ID: ${About.AXES}; orientation ${About.QUATERNION} (world: ${about.world}); stamps: ${about.time}",
            "covariance" to if (gyroscopeVariance > 0.0 || accelerometerVariance > 0.0) {
                "angular_velocity and linear_acceleration covariances: one sample's white-noise variance N^2 * f on the diagonal " +
                    "(gyroscope N = ${yamlNumber(noise!!.gyroscopeNoiseDensity)} rad/s/sqrt(Hz), accelerometer N = ${yamlNumber(noise.accelerometerNoiseDensity)} m/s^2/sqrt(Hz), " +
                    "f = ${yamlNumber(rateHz)} Hz, the gyroscope's rate, gaps left out); orientation and magnetic field covariances unknown (0)"
            } else {
                "unknown (0), no noise model given; orientation_covariance[0] = -1 on /imu/data_raw (not provided)"
            },
        )
        channels += channel(IMU_RAW, 1, "/imu/data_raw", metadata)
        channels += channel(IMU, 1, "/imu/data", metadata)
        if (hasMagnetometer) channels += channel(MAG, 2, "/imu/mag", metadata)
        for (r in schemas) out.write(r)
        for (r in channels) out.write(r)
    }

    private fun channel(id: Int, schema: Int, topic: String, metadata: Map<String, String>) = recordBytes(OP_CHANNEL) {
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

    /** A Message record into the chunk, indexed; the chunk is closed once it holds [CHUNK_BYTES]. */
    private inline fun message(channel: Int, ns: Long, body: Bytes.() -> Unit) {
        cdr.reset()
        cdr.u8(0); cdr.u8(1); cdr.u8(0); cdr.u8(0) // CDR_LE encapsulation
        cdr.origin = 4
        cdr.body()
        val offset = chunk.size.toLong()
        write(chunk, OP_MESSAGE) { u16(channel); u32((sequence[channel]++).toLong()); u64(ns); u64(ns); raw(cdr) }
        index[channel].u64(ns); index[channel].u64(offset)
        if (chunkMessages == 0) { chunkStart = ns; chunkEnd = ns } else { chunkStart = minOf(chunkStart, ns); chunkEnd = maxOf(chunkEnd, ns) }
        if (messages == 0L) { firstLogTime = ns; lastLogTime = ns } else { firstLogTime = minOf(firstLogTime, ns); lastLogTime = maxOf(lastLogTime, ns) }
        chunkMessages++
        messages++
        channelMessages[channel]++
        if (chunk.size >= CHUNK_BYTES) closeChunk()
    }

    /** Writes the chunk (uncompressed) and its message indexes, keeps its index entry. */
    private fun closeChunk() {
        if (chunkMessages == 0) return
        val crc = CRC32().apply { update(chunk.array, 0, chunk.size) }.value
        val start = out.position
        val fields = Bytes().apply { u64(chunkStart); u64(chunkEnd); u64(chunk.size.toLong()); u32(crc); string(""); u64(chunk.size.toLong()) }
        recordHeader(out, OP_CHUNK, fields.size.toLong() + chunk.size)
        out.write(fields.array, 0, fields.size)
        out.write(chunk.array, 0, chunk.size)
        val length = out.position - start
        val offsets = LongArray(CHANNELS + 1) { -1L }
        for (channel in 1..CHANNELS) {
            val entries = index[channel]
            if (entries.size == 0) continue
            offsets[channel] = out.position
            write(out, OP_MESSAGE_INDEX) { u16(channel); u32(entries.size.toLong()); raw(entries) }
            entries.reset()
        }
        chunks += ChunkEntry(chunkStart, chunkEnd, start, length, offsets, out.position - start - length, chunk.size.toLong())
        chunk.reset()
        chunkMessages = 0
    }

    /** One record [op] built by [content] into [to]. */
    private inline fun write(to: OutputStream, op: Int, content: Bytes.() -> Unit) {
        record.reset()
        record.content()
        recordHeader(to, op, record.size.toLong())
        to.write(record.array, 0, record.size)
    }

    private inline fun recordBytes(op: Int, content: Bytes.() -> Unit): ByteArray {
        val b = Bytes()
        write(b, op, content)
        return b.toByteArray()
    }

    private fun recordHeader(to: OutputStream, op: Int, length: Long) {
        to.write(op)
        for (k in 0 until 8) to.write(((length shr (8 * k)) and 0xff).toInt())
    }

    override fun close() {
        closeChunk()
        val dataCrc = out.crc.value
        write(out, OP_DATA_END) { u32(dataCrc) }
        val summaryStart = out.position
        out.crc.reset()
        val groups = ArrayList<LongArray>()
        fun group(op: Int, records: () -> Unit) {
            val start = out.position
            records()
            groups += longArrayOf(op.toLong(), start, out.position - start)
        }
        group(OP_SCHEMA) { for (r in schemas) out.write(r) }
        group(OP_CHANNEL) { for (r in channels) out.write(r) }
        group(OP_STATISTICS) {
            write(out, OP_STATISTICS) {
                u64(messages); u16(schemas.size); u32(channels.size.toLong()); u32(0); u32(0); u32(chunks.size.toLong())
                u64(firstLogTime); u64(lastLogTime)
                u32(channels.size * 10L)
                for (channel in 1..CHANNELS) if (channel != MAG || hasMagnetometer) { u16(channel); u64(channelMessages[channel]) }
            }
        }
        if (chunks.isNotEmpty()) group(OP_CHUNK_INDEX) {
            for (c in chunks) write(out, OP_CHUNK_INDEX) {
                u64(c.start); u64(c.end); u64(c.offset); u64(c.length)
                u32(c.indexOffsets.count { it >= 0 } * 10L)
                for (channel in 1..CHANNELS) if (c.indexOffsets[channel] >= 0) { u16(channel); u64(c.indexOffsets[channel]) }
                u64(c.indexLength); string(""); u64(c.size); u64(c.size)
            }
        }
        val summaryOffsetStart = out.position
        for (g in groups) write(out, OP_SUMMARY_OFFSET) { u8(g[0].toInt()); u64(g[1]); u64(g[2]) }
        recordHeader(out, OP_FOOTER, 20)
        val offsets = Bytes().apply { u64(summaryStart); u64(summaryOffsetStart) }
        out.write(offsets.array, 0, offsets.size)
        val summaryCrc = out.crc.value
        val crc = Bytes().apply { u32(summaryCrc) }
        out.write(crc.array, 0, crc.size)
        out.write(MAGIC)
        out.close()
    }

    /** A closed chunk as its Chunk Index tells it: log time range, file offset and length, each channel's message index offset (−1: none), their length, size. */
    private class ChunkEntry(val start: Long, val end: Long, val offset: Long, val length: Long, val indexOffsets: LongArray, val indexLength: Long, val size: Long)

    /** The file: every byte counted ([position], for the offsets) and summed into [crc]. */
    private class Sink(stream: OutputStream) : OutputStream() {
        private val out = BufferedOutputStream(stream, 1 shl 16)
        val crc = CRC32()
        var position = 0L
            private set

        override fun write(b: Int) { out.write(b); crc.update(b); position++ }
        override fun write(b: ByteArray, off: Int, len: Int) { out.write(b, off, len); crc.update(b, off, len); position += len }
        override fun flush() = out.flush()
        override fun close() = out.close()
    }

    /** A little-endian byte builder; [align] pads relative to [origin] (CDR: after the encapsulation). */
    internal class Bytes(capacity: Int = 256) : ByteArrayOutputStream(capacity) {
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
        private const val OP_CHUNK = 0x06
        private const val OP_MESSAGE_INDEX = 0x07
        private const val OP_CHUNK_INDEX = 0x08
        private const val OP_STATISTICS = 0x0B
        private const val OP_SUMMARY_OFFSET = 0x0E
        private const val OP_DATA_END = 0x0F
        private const val IMU_RAW = 1
        private const val IMU = 2
        private const val MAG = 3
        private const val CHANNELS = 3

        /** A chunk is closed once its records reach this size (1 MiB). */
        const val CHUNK_BYTES = 1 shl 20

        /**
         * The offered QoS of every channel, as rosbag2 stores it: a YAML list of profiles, each with
         * history, depth, reliability, durability, deadline, lifespan, liveliness,
         * liveliness_lease_duration (durations as sec and nsec) and avoid_ros_namespace_conventions,
         * the policies as rmw's enum numbers. Here rmw's sensor-data profile: keep last (1) 5, best
         * effort (2), volatile (2), durations unspecified (0, 0), liveliness system default (0).
         */
        val OFFERED_QOS_PROFILES = listOf(
            "- history: 1",
            "  depth: 5",
            "  reliability: 2",
            "  durability: 2",
            "  deadline:",
            "    sec: 0",
            "    nsec: 0",
            "  lifespan:",
            "    sec: 0",
            "    nsec: 0",
            "  liveliness: 0",
            "  liveliness_lease_duration:",
            "    sec: 0",
            "    nsec: 0",
            "  avoid_ros_namespace_conventions: false",
        ).joinToString("\n")

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
