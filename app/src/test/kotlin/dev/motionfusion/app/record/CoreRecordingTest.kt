package dev.motionfusion.app.record

import dev.motionfusion.app.export.Exporter
import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.lang.management.ManagementFactory
import java.util.concurrent.atomic.AtomicLong
import java.util.concurrent.atomic.AtomicReference
import kotlin.math.abs

/** The recorder on the real session format of fusion-core: flood, kill and recovery, export and replay. */
class CoreRecordingTest {
    @TempDir
    lateinit var tmp: File

    private val metadata = SessionMetadata(
        appVersion = "test", source = "CoreRecordingTest", startAnchor = ClockAnchor(1_764_165_792_123L, 1_000_000_000L),
        filterSettings = FilterSettings(),
    )

    private fun threadAllocated(id: Long): Long =
        (ManagementFactory.getThreadMXBean() as com.sun.management.ThreadMXBean).getThreadAllocatedBytes(id)

    @Test
    fun `the capture path allocates nothing per event, live and recording`() {
        val c = TestCapture(publishIntervalNs = Long.MAX_VALUE / 4) // the state snapshot is per frame, not per event: left out here
        // Diagnostics rows (10 per second of sensor time, each a small snapshot) are counted apart.
        val recorder = Recorder(CoreSessionFormat.create(File(tmp, "alloc"), metadata), onEnd = {}, diagnosticsIntervalNs = Long.MAX_VALUE / 4)
        c.record(recorder)
        val v = floatArrayOf(0.1f, 0.2f, 9.8f, 0.01f, 0.02f, 0.03f)
        val streams = SensorStreams.all
        var t = 1_000_000_000L
        fun deliver(n: Int) {
            // Out of order as Android delivers it: each stream's batch of 8 in turn.
            var i = 0
            while (i < n) {
                for (s in streams) for (k in 0 until 8) c.ring.offer(s, t + k * 300_000L, 3, v, s.valueCount)
                t += 8 * 300_000L
                i += 8 * streams.size
                c.capture.pump()
            }
        }
        deliver(20_000) // warm up: stream files opened, classes loaded, code compiled
        val me = Thread.currentThread().id
        val before = threadAllocated(me)
        deliver(100_800)
        val bytes = threadAllocated(me) - before
        val perEvent = bytes / 100_800.0
        c.stop(recorder)
        println("capture path (ring, reorder window, live filter, recorder, session writer): %d bytes for 100,800 events, %.3f bytes per event".format(bytes, perEvent))
        // Measured 0.51 B per event: no per-event object (that would be ≥ 16 B each); the rest comes in
        // per batch or per written buffer, not yet attributed further.
        assertTrue(perEvent < 1.0, "allocated $perEvent bytes per event")
    }

    /**
     * A recording of a simulated motion through the capture, delivered as Android does: each
     * sensor's batch of [batch] events in turn (so the merged stream steps back by up to a batch),
     * the capture thread pumping between batches.
     */
    private fun recordSimulated(dir: File, seconds: Double, stopAtEnd: Boolean = true, batch: Int = 5, latencyUs: Int = 0): Pair<Recorder, TestCapture> {
        val sim = MotionSimulator(SimulationSettings(seed = 7, rateHz = 200.0, durationS = seconds)).run().toList()
        val c = TestCapture(latencyUs = latencyUs)
        val recorder = Recorder(CoreSessionFormat.create(dir, metadata.copy(filterSettings = c.capture.filterSettingsFor(c.settings.value))), onEnd = {}, flushIntervalNs = 100_000_000L)
        c.record(recorder)
        if (latencyUs > 0) deliverBatched(c, sim, latencyUs * 1000L)
        else for (chunk in sim.chunked(batch)) {
            for (s in chunk) c.offer(SessionStream.GYROSCOPE, s.timestampNs + 200_000, s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat())
            c.capture.pump()
            for (s in chunk) c.offer(SessionStream.ACCELEROMETER, s.timestampNs, s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat())
            for (s in chunk) {
                val q = s.truth
                c.offer(SessionStream.ROTATION_VECTOR, s.timestampNs + 300_000, q.x.toFloat(), q.y.toFloat(), q.z.toFloat(), q.w.toFloat(), 0.1f)
            }
            c.capture.pump()
            for (s in chunk) c.offer(SessionStream.MAGNETOMETER, s.timestampNs + 100_000, s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat())
            c.nowNs = chunk.last().timestampNs
            c.capture.pump()
        }
        c.drain()
        c.nowNs += 1_000_000_000L
        c.capture.pump() // the quiet capture empties the reorder window; the last flush
        assertEquals(0L, c.capture.lateEvents, "every event was put in order")
        if (stopAtEnd) c.stop(recorder)
        return recorder to c
    }

    /**
     * The simulated motion delivered as sensors with hardware FIFOs deliver it while nothing is on
     * screen: each sensor's events gathered for [latencyNs] and handed over whole, the gyroscope's,
     * the accelerometer's with the rotation vector's (one shared FIFO) and the magnetometer's at
     * their own phases, the capture thread pumping after each sensor's batch.
     */
    private fun deliverBatched(c: TestCapture, sim: List<dev.motionfusion.core.sim.SimulatedSample>, latencyNs: Long) {
        class E(val stream: SessionStream, val t: Long, val v: FloatArray)
        val events = ArrayList<E>()
        for (s in sim) {
            events += E(SessionStream.GYROSCOPE, s.timestampNs + 200_000, floatArrayOf(s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat()))
            events += E(SessionStream.ACCELEROMETER, s.timestampNs, floatArrayOf(s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat()))
            val q = s.truth
            events += E(SessionStream.ROTATION_VECTOR, s.timestampNs + 300_000, floatArrayOf(q.x.toFloat(), q.y.toFloat(), q.z.toFloat(), q.w.toFloat(), 0.1f))
            events += E(SessionStream.MAGNETOMETER, s.timestampNs + 100_000, floatArrayOf(s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat()))
        }
        val phase = mapOf(
            SessionStream.GYROSCOPE to 0L, SessionStream.ACCELEROMETER to latencyNs * 2 / 5,
            SessionStream.ROTATION_VECTOR to latencyNs * 2 / 5, SessionStream.MAGNETOMETER to latencyNs * 3 / 4,
        )
        val order = listOf(SessionStream.GYROSCOPE, SessionStream.ROTATION_VECTOR, SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER)
        for (b in dev.motionfusion.app.sensor.FifoBatches.of(events, { it.stream }, { it.t }, latencyNs, { phase.getValue(it) }, order)) {
            c.nowNs = b.deliveredNs
            for (e in b.events) c.offer(e.stream, e.t, *e.v)
            c.capture.pump()
        }
    }

    /**
     * The filter run again on the written raw streams, merged by timestamp as `fusion replay`
     * does; the reader gives each value as the float it was written from, as the live filter saw it.
     */
    private fun replayOrientation(reader: SessionReader, settings: FilterSettings = FilterSettings()): List<Pair<Long, DoubleArray>> {
        val filter = MadgwickFilter(settings)
        val out = ArrayList<Pair<Long, DoubleArray>>()
        val v = DoubleArray(3)
        reader.events(setOf(SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE)).use { e ->
            while (e.next()) {
                for (k in 0..2) v[k] = e.values[k]
                when (e.stream) {
                    SessionStream.ACCELEROMETER -> filter.updateAccelerometer(e.timestampNs, v[0], v[1], v[2])
                    SessionStream.MAGNETOMETER -> filter.updateMagnetometer(e.timestampNs, v[0], v[1], v[2])
                    SessionStream.GYROSCOPE -> {
                        filter.updateGyroscope(e.timestampNs, v[0], v[1], v[2])
                        if (filter.isInitialised) out += e.timestampNs to DoubleArray(4).also { filter.orientationInto(it) }
                    }
                    else -> Unit
                }
            }
        }
        return out
    }

    private fun liveOrientation(reader: SessionReader): List<Pair<Long, DoubleArray>> {
        val out = ArrayList<Pair<Long, DoubleArray>>()
        reader.stream(SessionStream.ORIENTATION).use { e -> while (e.next()) out += e.timestampNs to e.values.copyOf() }
        return out
    }

    /**
     * Rotation angle between two unit quaternions, degrees, from the chord |a − ±b| = 2·sin(φ/2)
     * (φ the angle between them on the 3-sphere, the rotation angle 2φ): unlike acos of the dot
     * product, exact for tiny differences such as the float rounding of the stored quaternions.
     */
    private fun angleDeg(a: DoubleArray, b: DoubleArray): Double {
        val sign = if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0) -1.0 else 1.0
        val chord = kotlin.math.sqrt((0..3).sumOf { (a[it] - sign * b[it]).let { d -> d * d } })
        return Math.toDegrees(4 * kotlin.math.asin((chord / 2).coerceAtMost(1.0)))
    }

    @Test
    fun `an exported zip replays to the same orientation as the live output`() = replaysAsLive(latencyUs = 0)

    /** The same with the sensors' batches of 2 s delivered separately, as hardware batching with nothing on screen does. */
    @Test
    fun `with hardware batching the replay still equals the live output`() = replaysAsLive(latencyUs = 2_000_000)

    private fun replaysAsLive(latencyUs: Int) {
        val dir = File(tmp, "session_motion")
        val (_, c) = recordSimulated(dir, 20.0, latencyUs = latencyUs)
        if (latencyUs > 0) assertEquals(dev.motionfusion.app.fusion.Capture.windowFor(latencyUs), c.capture.reorderWindowNs)
        val zip = File(tmp, "out/session_motion.zip")
        Exporter.writeZip(dir, zip)
        SessionReader.open(zip.toPath()).use { r ->
            assertEquals("session_motion.zip", r.name)
            val live = liveOrientation(r)
            val replay = replayOrientation(r)
            assertEquals(4000, live.size, "one orientation row per gyroscope row, the first from initialisation")
            assertEquals(live.map { it.first }, replay.map { it.first })
            val worst = live.indices.maxOf { angleDeg(live[it].second, replay[it].second) }
            val viaMeta = replayOrientation(r, r.metadata.filterSettings!!)
            val worstMeta = live.indices.maxOf { angleDeg(live[it].second, viaMeta[it].second) }
            println(
                "export: live vs replay of the zip over ${live.size} steps: worst %.2e° (meta.json's filter settings: %.2e°)"
                    .format(worst, worstMeta),
            )
            assertTrue(worstMeta < 1e-4, "with the settings in meta.json: $worstMeta°")
            // The replay engine of `fusion replay` on the zip itself.
            val cli = ArrayList<DoubleArray>()
            dev.motionfusion.core.input.Recording.open(zip.toPath()).use { rec ->
                assertEquals(dev.motionfusion.core.input.RecordingFormat.SESSION, rec.format)
                rec.events().use { e ->
                    dev.motionfusion.core.replay.Replayer().run(e, rec.originNs, object : dev.motionfusion.core.replay.ReplayListener {
                        override fun step(step: dev.motionfusion.core.replay.ReplayStep) {
                            if (step.initialised) cli += step.orientation.copyOf()
                        }
                    })
                }
            }
            assertEquals(live.size, cli.size)
            val worstCli = live.indices.maxOf { angleDeg(live[it].second, cli[it]) }
            println("export: fusion replay's engine on the zip vs live: worst %.2e°".format(worstCli))
            assertTrue(worstCli < 1e-4, "fusion replay: $worstCli°")
            // The live output is stored as float: agreement to float precision, not a coarse tolerance.
            assertTrue(worst < 1e-4, "worst difference $worst°")
            // And the recording is a real motion: orientation changes by far more than that.
            assertTrue(angleDeg(live.first().second, live.last().second) > 5.0)
        }
    }

    @Test
    fun `killed mid-recording, the session is recovered on the next start and reads back`() {
        val dir = File(tmp, "session_killed")
        val (recorder, _) = recordSimulated(dir, 5.0, stopAtEnd = false)
        // After a flush of the complete data, "kill": the recorder is abandoned without closing,
        // and one file ends in a partial row as a killed write leaves it.
        val acc = File(dir, SessionStream.ACCELEROMETER.fileName)
        acc.appendText("6123456789,0.12")
        assertTrue(CoreSessionFormat.isInterrupted(dir))
        val rowsBefore = recorder.rowCount
        assertEquals(4000L, rowsBefore)

        CoreSessionFormat.recover(dir)
        assertFalse(CoreSessionFormat.isInterrupted(dir))
        SessionReader.open(dir.toPath()).use { r ->
            assertTrue(r.metadata.recovered)
            assertTrue(r.metadata.complete)
            val counts = SensorStreams.all.filter { it in r.streams }.associateWith { r.metadata.streams.getValue(it).samples }
            assertEquals(mapOf(SessionStream.ACCELEROMETER to 1000L, SessionStream.MAGNETOMETER to 1000L, SessionStream.GYROSCOPE to 1000L, SessionStream.ROTATION_VECTOR to 1000L), counts)
            assertFalse(acc.readText().contains("6123456789"), "the partial row is cut")
            val replay = replayOrientation(r)
            val live = liveOrientation(r)
            assertEquals(1000, replay.size)
            assertEquals(live.size, replay.size)
        }
    }
    @Test
    fun `storage failing after N bytes stops the recording cleanly and keeps every row that reached it`() {
        // A stream that fails after N bytes, on the real writer: gyroscope.csv is a named pipe
        // whose reader keeps the first N bytes (what "storage" got) and then goes away, so the
        // writer's next write fails with an IOException as on a full or removed disk.
        val dir = File(tmp, "session_failing").apply { mkdirs() }
        val gyro = File(dir, SessionStream.GYROSCOPE.fileName)
        org.junit.jupiter.api.Assumptions.assumeTrue(
            runCatching { ProcessBuilder("mkfifo", gyro.path).start().waitFor() == 0 }.getOrDefault(false), "needs mkfifo",
        )
        val limit = 50_000
        val stored = java.io.ByteArrayOutputStream()
        val storage = Thread {
            java.io.FileInputStream(gyro).use { input ->
                val buf = ByteArray(4096)
                var left = limit
                while (left > 0) {
                    val n = input.read(buf, 0, minOf(buf.size, left))
                    if (n < 0) break
                    stored.write(buf, 0, n)
                    left -= n
                }
            }
        }.apply { start() }
        val c = TestCapture()
        val ended = AtomicReference<RecorderResult>()
        val recorder = Recorder(CoreSessionFormat.create(dir, metadata), onEnd = { ended.set(it) }, flushIntervalNs = 20_000_000L)
        c.record(recorder)
        var offered = 0
        val t0 = 5_000_000_000L
        while (ended.get() == null && offered < 200_000) {
            val t = t0 + offered * 1_000_000L
            val s = if (offered % 2 == 0) SessionStream.ACCELEROMETER else SessionStream.GYROSCOPE
            c.offer(s, t, offered.toFloat(), 0f, 9.81f)
            offered++
            c.nowNs = t
            if (offered % 100 == 0) c.capture.pump()
        }
        assertTrue(ended.get() != null, "the recording ended")
        storage.join(5_000)
        val end = ended.get().end
        assertTrue(end is RecordingEnd.WriteFailed, "$end")
        println("storage failure: ${(end as RecordingEnd.WriteFailed).message} after $limit bytes of gyroscope.csv; ${ended.get().rows} rows handed to the writer")

        // What the storage holds replaces the pipe; the next start finds the session interrupted and repairs it.
        gyro.delete()
        gyro.writeBytes(stored.toByteArray())
        assertTrue(CoreSessionFormat.isInterrupted(dir))
        CoreSessionFormat.recover(dir)
        SessionReader.open(dir.toPath()).use { r ->
            assertTrue(r.metadata.recovered)
            assertEquals("write_failed: Broken pipe", r.metadata.endReason)
            // Every complete gyroscope row that reached storage is there, in order, from the first.
            var k = 0L
            r.stream(SessionStream.GYROSCOPE).use { e ->
                while (e.next()) {
                    assertEquals(t0 + (2 * k + 1) * 1_000_000L, e.timestampNs)
                    assertEquals((2 * k + 1).toDouble(), e.values[0])
                    k++
                }
            }
            val completeLines = stored.toByteArray().count { it == '\n'.code.toByte() } - 1 // minus the header
            assertEquals(completeLines.toLong(), k)
            assertTrue(k > 1000, "$k gyroscope rows")
            // The accelerometer, drained when the writer was abandoned, holds every row handed to the writer.
            var a = 0L
            r.stream(SessionStream.ACCELEROMETER).use { e ->
                while (e.next()) {
                    assertEquals(t0 + 2 * a * 1_000_000L, e.timestampNs)
                    a++
                }
            }
            println("storage failure: recovered $k gyroscope rows (all that reached storage) and $a accelerometer rows")
            assertEquals(ended.get().rowsPerStream[SessionStream.ACCELEROMETER.ordinal], a)
        }
    }
}
