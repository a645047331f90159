package dev.motionfusion.app.export

import android.app.Activity
import android.content.Intent
import android.net.Uri
import android.widget.Button
import android.widget.CheckBox
import android.widget.TextView
import com.google.android.material.chip.Chip
import com.google.android.material.chip.ChipGroup
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.platform.Failure
import dev.motionfusion.app.platform.NoiseTooShortException
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.RecordingEnd
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.replay.HeadingTare
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode
import java.io.ByteArrayInputStream
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.zip.ZipInputStream
import kotlin.math.abs
import kotlin.math.sqrt

/**
 * The session detail's export formats, written by fusion-core's exporters (as `fusion export`) from a
 * recorded session and read back: every format's header, its rows and its first and last timestamps
 * equal to the session's gyroscope samples; the heading zeroed at the start; a still recording's
 * noise configurations; the chooser on the detail screen, rendered.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class SessionExportFormatsTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        graph = TestGraph()
    }

    /** [seconds] of simulated motion at 100 Hz as the app records it (accelerometer, magnetometer, gyroscope, each its own time). */
    private fun session(name: String, seconds: Double, still: Boolean = false): File = offMainThread {
        val dir = File(File(app.filesDir, "sessions"), name)
        val meta = SessionMetadata(appVersion = "0.1.0", startAnchor = ClockAnchor(1_795_684_500_000L, 1_000_000_000L), filterSettings = FilterSettings(), stillRecording = still)
        val sink = CoreSessionFormat.create(dir, meta)
        val settings = if (still) {
            SimulationSettings(seed = 5, rateHz = 100.0, durationS = seconds, angularRate = 0.0, gyroNoise = 0.0, accNoise = 0.0, gyroNoiseDensity = 0.001, accNoiseDensity = 0.02)
        } else {
            SimulationSettings(seed = 3, rateHz = 100.0, durationS = seconds)
        }
        for (s in MotionSimulator(settings).run()) {
            sink.raw(SessionStream.ACCELEROMETER, s.timestampNs, 3, floatArrayOf(s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat()), 0)
            if (!still) sink.raw(SessionStream.MAGNETOMETER, s.timestampNs + 1_000, 3, floatArrayOf(s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat()), 0)
            sink.raw(SessionStream.GYROSCOPE, s.timestampNs + 2_000, 3, floatArrayOf(s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat()), 0)
        }
        sink.finish(RecordingEnd.Stopped)
        dir
    }

    /** The session's timestamps of [stream]. */
    private fun times(dir: File, stream: SessionStream): List<Long> = offMainThread {
        SessionReader.open(dir.toPath()).use { r -> r.stream(stream).use { e -> buildList { while (e.next()) add(e.timestampNs) } } }
    }

    private fun export(dir: File, choice: ExportChoice): ByteArray = offMainThread {
        val target = File(app.cacheDir, "out/" + choice.kind.fileName(dir.name))
        Exporter.writeZip(dir, target, choice)
        target.readBytes()
    }

    private fun unzip(bytes: ByteArray): Map<String, String> = ZipInputStream(ByteArrayInputStream(bytes)).use { z ->
        buildMap { while (true) { val e = z.nextEntry ?: break; put(e.name, z.readBytes().toString(Charsets.UTF_8)) } }
    }

    private fun rows(csv: String): List<List<String>> = csv.lines().drop(1).filter { it.isNotBlank() }.map { it.split(',') }

    @Test
    fun `each format read back, header, rows and first and last timestamps as the session has them`() {
        val dir = session("walk", 6.0)
        val gyro = times(dir, SessionStream.GYROSCOPE)
        val mag = times(dir, SessionStream.MAGNETOMETER)
        assertEquals(600, gyro.size)

        val euroc = unzip(export(dir, ExportChoice(ExportKind.EUROC)))
        val imu = euroc.getValue("walk-euroc/mav0/imu0/data.csv")
        assertEquals("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]", imu.lines()[0])
        assertEquals(gyro, rows(imu).map { it[0].toLong() })
        assertEquals(mag, rows(euroc.getValue("walk-euroc/mav0/mag0/data.csv")).map { it[0].toLong() })
        val pose = rows(euroc.getValue("walk-euroc/mav0/state_groundtruth_estimate0/data.csv"))
        assertEquals(gyro.last(), pose.last()[0].toLong())
        assertTrue("sensor.yaml", "rate_hz:" in euroc.getValue("walk-euroc/mav0/imu0/sensor.yaml"))

        val kalibr = unzip(export(dir, ExportChoice(ExportKind.KALIBR)))
        assertEquals(setOf("walk-kalibr/imu.yaml", "walk-kalibr/imu0.csv"), kalibr.keys)
        val k = kalibr.getValue("walk-kalibr/imu0.csv")
        assertEquals("timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z", k.lines()[0])
        assertEquals(gyro, rows(k).map { it[0].toLong() })

        val gcsv = String(export(dir, ExportChoice(ExportKind.GCSV)), Charsets.UTF_8)
        val lines = gcsv.lines().filter { it.isNotBlank() }
        assertEquals(listOf("GYROFLOW IMU LOG", "version,1.3"), lines.take(2))
        val header = lines.indexOf("t,gx,gy,gz,ax,ay,az,mx,my,mz")
        assertTrue(gcsv, header > 0)
        // With a magnetometer, rows from the first gyroscope sample after the first of both (here the first).
        assertEquals(gyro, lines.drop(header + 1).map { it.substringBefore(',').toLong() })

        val mcap = McapRead(export(dir, ExportChoice(ExportKind.ROS2)))
        assertEquals(gyro, mcap.logTimes.getValue("/imu/data_raw"))
        assertEquals(pose.map { it[0].toLong() }, mcap.logTimes.getValue("/imu/data"))
        assertEquals(mag, mcap.logTimes.getValue("/imu/mag"))
        println("app exports of a 6-s session: euroc ${gyro.size} IMU / ${pose.size} pose / ${mag.size} mag rows, kalibr ${gyro.size}, gcsv ${gyro.size}, " +
            "ros2 ${gyro.size} + ${pose.size} + ${mag.size} messages; first/last ${gyro.first()}/${gyro.last()} ns in each")
    }

    @Test
    fun `zero heading at start, the first exported orientation reads heading 0, pitch and roll kept`() {
        val dir = session("turn", 4.0)
        fun firstPose(choice: ExportChoice): DoubleArray {
            val pose = rows(unzip(export(dir, choice)).getValue("turn-euroc/mav0/state_groundtruth_estimate0/data.csv"))
            return DoubleArray(4) { pose[0][4 + it].toDouble() }
        }
        val plain = firstPose(ExportChoice(ExportKind.EUROC))
        val tared = firstPose(ExportChoice(ExportKind.EUROC, zeroHeading = true))
        val before = Math.toDegrees(HeadingTare.heading(plain))
        assertTrue("the simulated start is not already at heading 0: $before", abs(before) > 5)
        assertEquals(0.0, Math.toDegrees(HeadingTare.heading(tared)), 1e-5)
        // Turned about up only: the up axis seen from the device is unchanged.
        val up = { q: DoubleArray -> Quaternion(q[0], q[1], q[2], q[3]).conjugate().rotate(dev.motionfusion.core.Vector3(0.0, 0.0, 1.0)) }
        val a = up(plain)
        val b = up(tared)
        assertEquals(a.x, b.x, 1e-7); assertEquals(a.y, b.y, 1e-7); assertEquals(a.z, b.z, 1e-7)
        // Not for formats without the orientation: Kalibr's rows are the same with or without.
        assertEquals(unzip(export(dir, ExportChoice(ExportKind.KALIBR))).getValue("turn-kalibr/imu0.csv"),
            unzip(export(dir, ExportChoice(ExportKind.KALIBR, zeroHeading = true))).getValue("turn-kalibr/imu0.csv"))
    }

    @Test
    fun `a still recording gives its noise model as kalibr, OpenVINS, VINS and ORB-SLAM3 files, each with its conversion`() {
        val dir = session("still", 90.0, still = true)
        val files = unzip(export(dir, ExportChoice(ExportKind.NOISE)))
        assertEquals(listOf("imu.yaml", "kalibr_imu_chain.yaml", "orbslam3_imu.yaml", "vins_imu.yaml").map { "still-noise/$it" }, files.keys.sorted())
        fun value(file: String, key: String): Double =
            files.getValue("still-noise/$file").lines().first { it.trim().startsWith("$key:") }.substringAfter(':').substringBefore('#').trim().toDouble()
        val n = value("imu.yaml", "gyroscope_noise_density")
        val f = value("imu.yaml", "update_rate")
        assertEquals(0.001, n, 0.0002) // the simulated density, read off the Allan deviation
        assertEquals(100.0, f, 0.1)
        assertEquals(n * sqrt(f), value("vins_imu.yaml", "gyr_n"), 1e-5 * n * sqrt(f))
        assertEquals(n, value("orbslam3_imu.yaml", "IMU.NoiseGyro"), 1e-5 * n)
        assertTrue(files.getValue("still-noise/kalibr_imu_chain.yaml").contains("CONTINUOUS-TIME"))
    }

    @Test
    fun `a still recording too short for noise figures fails with a clear reason`() {
        val dir = session("short", 10.0, still = true)
        val e = runCatching { export(dir, ExportChoice(ExportKind.NOISE)) }.exceptionOrNull()
        assertTrue("$e", e is NoiseTooShortException)
        assertEquals(Failure.NOISE_TOO_SHORT, Failure.of(e!!, "test"))
        assertTrue("nothing left", offMainThread { File(app.cacheDir, "out").listFiles()?.none { it.name.startsWith("short") } ?: true })
    }

    private fun detail(dir: File): SessionDetailActivity {
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, dir.name)
        val a = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
        graph.settle()
        return a
    }

    private fun chip(a: Activity, label: Int): Chip {
        val group = a.findViewById<ChipGroup>(R.id.detail_formats)
        return (0 until group.childCount).map { group.getChildAt(it) as Chip }.single { it.text == a.getString(label) }
    }

    @Test
    fun `the detail offers every format, and Share writes the chosen one with the heading zeroed`() {
        val dir = session("walk", 6.0)
        Robolectric.setupContentProvider(ExportProvider::class.java, ExportProvider.authority(app))
        val a = detail(dir)
        val group = a.findViewById<ChipGroup>(R.id.detail_formats)
        assertEquals(listOf(R.string.export_format_session, R.string.export_format_euroc, R.string.export_format_kalibr, R.string.export_format_ros2, R.string.export_format_gcsv).map { a.getString(it) },
            (0 until group.childCount).map { (group.getChildAt(it) as Chip).text.toString() })
        assertTrue("the session's zip by default", chip(a, R.string.export_format_session).isChecked)
        val tare = a.findViewById<CheckBox>(R.id.detail_zero_heading)
        assertTrue("no heading in the session's zip", !tare.isEnabled)
        Screenshots.capture(a, "session-detail-formats")

        chip(a, R.string.export_format_euroc).performClick()
        graph.settle()
        assertTrue(tare.isEnabled)
        tare.performClick()
        graph.settle()
        assertTrue(tare.isChecked)
        assertEquals(a.getString(R.string.export_about_euroc), a.findViewById<TextView>(R.id.detail_format_about).text.toString())
        tare.jumpDrawablesToCurrentState() // the check mark's animation at its end, as on screen a moment later
        Screenshots.capture(a, "session-detail-formats-euroc")
        a.findViewById<Button>(R.id.detail_share).performClick()
        graph.settle()
        val chooser = shadowOf(a).nextStartedActivity
        @Suppress("DEPRECATION")
        val send = chooser.getParcelableExtra<Intent>(Intent.EXTRA_INTENT)!!
        assertEquals("application/zip", send.type)
        @Suppress("DEPRECATION")
        val uri = send.getParcelableExtra<Uri>(Intent.EXTRA_STREAM)!!
        assertEquals("walk-euroc.zip", uri.lastPathSegment)
        val bytes = offMainThread { app.contentResolver.openInputStream(uri)!!.use { it.readBytes() } }
        val pose = rows(unzip(bytes).getValue("walk-euroc/mav0/state_groundtruth_estimate0/data.csv"))
        assertEquals(0.0, Math.toDegrees(HeadingTare.heading(DoubleArray(4) { pose[0][4 + it].toDouble() })), 1e-5)

        // ROS 2: one MCAP file, its own type.
        chip(a, R.string.export_format_ros2).performClick()
        graph.settle()
        a.findViewById<Button>(R.id.detail_share).performClick()
        graph.settle()
        @Suppress("DEPRECATION")
        val mcap = shadowOf(a).nextStartedActivity.getParcelableExtra<Intent>(Intent.EXTRA_INTENT)!!
        assertEquals("application/octet-stream", mcap.type)
        @Suppress("DEPRECATION")
        val mcapUri = mcap.getParcelableExtra<Uri>(Intent.EXTRA_STREAM)!!
        assertEquals("walk.mcap", mcapUri.lastPathSegment)
        assertEquals("application/octet-stream", app.contentResolver.getType(mcapUri))
    }

    @Test
    fun `a still recording offers its noise model, and when too short the failure says why`() {
        val dir = session("still", 10.0, still = true)
        val a = detail(dir)
        chip(a, R.string.export_format_noise).performClick()
        graph.settle()
        Screenshots.capture(a, "session-detail-formats-noise")
        a.findViewById<Button>(R.id.detail_share).performClick()
        graph.settle()
        assertEquals(a.getString(R.string.export_failed, a.getString(R.string.failure_noise_too_short)), a.findViewById<TextView>(R.id.detail_message).text.toString())
    }

    @Test
    @Config(qualifiers = "de-w360dp-h640dp")
    fun `in German on a small phone the formats wrap and the failure is said in German`() {
        val dir = session("ruhe", 10.0, still = true)
        val a = detail(dir)
        assertEquals("Rauschmodell (VIO)", chip(a, R.string.export_format_noise).text.toString())
        chip(a, R.string.export_format_noise).performClick()
        graph.settle()
        a.findViewById<Button>(R.id.detail_share).performClick()
        graph.settle()
        assertEquals("Export fehlgeschlagen: Rauschwerte brauchen eine Ruheaufnahme von mindestens 1 Minute (Stunden für den Random Walk)",
            a.findViewById<TextView>(R.id.detail_message).text.toString())
        Screenshots.capture(a, "session-detail-formats-de-small", width = 720, height = 1280)
    }

    /** The topics of an MCAP file's channels and each one's message log times, read record by record (opcode, u64 length, content). */
    /** The log times of every message per topic, read through the chunks (a Channel record may repeat in the summary). */
    private class McapRead(bytes: ByteArray) {
        val logTimes = LinkedHashMap<String, MutableList<Long>>()
        private val topics = HashMap<Int, String>()

        init {
            val magic = byteArrayOf(0x89.toByte(), 'M'.code.toByte(), 'C'.code.toByte(), 'A'.code.toByte(), 'P'.code.toByte(), '0'.code.toByte(), '\r'.code.toByte(), '\n'.code.toByte())
            assertTrue("leading magic", bytes.copyOfRange(0, 8).contentEquals(magic))
            assertTrue("trailing magic", bytes.copyOfRange(bytes.size - 8, bytes.size).contentEquals(magic))
            assertTrue("footer", records(ByteBuffer.wrap(bytes, 8, bytes.size - 16).order(ByteOrder.LITTLE_ENDIAN)))
        }

        /** Reads the records of [b] to its end; true when one was the footer. */
        private fun records(b: ByteBuffer): Boolean {
            var footer = false
            while (b.hasRemaining()) {
                val op = b.get().toInt() and 0xff
                val len = b.long.toInt()
                val start = b.position()
                when (op) {
                    0x04 -> {
                        val id = b.short.toInt() and 0xffff
                        b.short
                        val n = b.int
                        val topic = ByteArray(n).also { b.get(it) }.toString(Charsets.UTF_8)
                        topics[id] = topic
                        logTimes.getOrPut(topic) { ArrayList() }
                    }
                    0x05 -> {
                        val id = b.short.toInt() and 0xffff
                        b.int
                        logTimes.getValue(topics.getValue(id)) += b.long
                    }
                    0x06 -> {
                        b.long; b.long; b.long; b.int // start and end time, uncompressed size and CRC
                        val compression = b.int
                        assertEquals("uncompressed chunks", 0, compression)
                        val n = b.long.toInt()
                        records(ByteBuffer.wrap(b.array(), b.arrayOffset() + b.position(), n).slice().order(ByteOrder.LITTLE_ENDIAN))
                    }
                    0x02 -> footer = true
                }
                b.position(start + len)
            }
            return footer
        }
    }
}
