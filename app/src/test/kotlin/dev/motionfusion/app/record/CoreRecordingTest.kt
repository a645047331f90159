package dev.motionfusion.app.record

import dev.motionfusion.app.export.Exporter
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionStream
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
    fun `a flood of 1,050,000 events across all streams gives exactly that many rows on disk, in order, memory bounded`() {
        val dir = File(tmp, "flood")
        val ring = EventRing(RecordingDeps.ringCapacity)
        val sink = CoreSessionFormat.create(dir, metadata)
        val ended = AtomicReference<RecorderResult>()
        val recorder = Recorder(ring, sink, MadgwickFilter(), onEnd = { ended.set(it) })
        val streams = SensorStreams.all
        val perStream = 150_000
        val total = perStream * streams.size
        val rateHz = 150_000.0 // ~40× a phone giving all seven streams at 500 Hz
        val heapPeak = AtomicLong()
        val mem = ManagementFactory.getMemoryMXBean()
        System.gc()
        val heapBefore = mem.heapMemoryUsage.used
        val monitor = Thread {
            while (!Thread.currentThread().isInterrupted) {
                heapPeak.accumulateAndGet(mem.heapMemoryUsage.used, ::maxOf)
                try { Thread.sleep(20) } catch (_: InterruptedException) { break }
            }
        }.apply { isDaemon = true; start() }
        recorder.start()
        var producerAllocated = 0L
        var maxQueued = 0
        val t0 = System.nanoTime()
        val producer = Thread {
            val id = Thread.currentThread().id
            val before = threadAllocated(id)
            val v = FloatArray(6)
            for (i in 0 until total) {
                // Paced like a sensor delivering batches from its FIFO: every millisecond the
                // events due by then; never waits for the writer.
                val due = t0 + (i / rateHz * 1e9).toLong()
                while (System.nanoTime() < due) java.util.concurrent.locks.LockSupport.parkNanos(1_000_000L)
                val s = streams[i % streams.size]
                v[0] = i.toFloat(); v[1] = 1f; v[2] = 9.81f; v[3] = 0.5f; v[4] = -0.5f; v[5] = 0.25f
                if (s == SessionStream.MAGNETOMETER) { v[1] = 22f; v[2] = -40f }
                check(ring.offer(s, 2_000_000_000L + i * 1_000L, 3, v, s.valueCount)) { "refused event $i" }
                if ((i and 1023) == 0) maxQueued = maxOf(maxQueued, ring.size)
            }
            producerAllocated = threadAllocated(id) - before
        }
        producer.start()
        producer.join()
        val produced = System.nanoTime() - t0
        recorder.stop()
        assertTrue(recorder.awaitEnd(60_000))
        val elapsed = System.nanoTime() - t0
        monitor.interrupt()
        val result = ended.get()
        assertEquals(RecordingEnd.Stopped, result.end)
        assertEquals(total.toLong(), result.rows)
        SessionReader.open(dir.toPath()).use { assertEquals("stopped", it.metadata.endReason) }
        assertEquals(0L, result.refused)

        // Every row on disk, per stream in order, with its value.
        var rows = 0L
        SessionReader.open(dir.toPath()).use { r ->
            assertTrue(r.metadata.complete)
            for ((k, s) in streams.withIndex()) {
                var expected = k.toLong()
                r.stream(s).use { e ->
                    while (e.next()) {
                        assertEquals(2_000_000_000L + expected * 1_000L, e.timestampNs)
                        assertEquals(expected.toFloat().toDouble(), e.values[0])
                        assertEquals(3, e.accuracy)
                        expected += streams.size
                        rows++
                    }
                }
                assertEquals(perStream.toLong(), r.metadata.streams.getValue(s).samples)
            }
            assertEquals(result.fusedRows, r.metadata.streams.getValue(SessionStream.ORIENTATION).samples)
        }
        assertEquals(total.toLong(), rows)
        val heapGrowth = heapPeak.get() - heapBefore
        val bytes = SensorStreams.all.sumOf { File(dir, it.fileName).length() }
        println(
            "flood: %,d events, %,d rows on disk (%,d bytes), produced in %.2f s, all written after %.2f s; ".format(total, rows, bytes, produced / 1e9, elapsed / 1e9) +
                "max queued %,d of %,d; producer allocated %,d bytes; heap before %.1f MB, peak %.1f MB (growth %.1f MB)".format(
                    maxQueued, ring.capacity, producerAllocated, heapBefore / 1e6, heapPeak.get() / 1e6, heapGrowth / 1e6,
                ),
        )
        assertTrue(producerAllocated < 64 * 1024, "the sensor side allocated $producerAllocated bytes")
        assertTrue(maxQueued < ring.capacity)
    }

    @Test
    fun `the writer thread allocates nothing per event`() {
        val dir = File(tmp, "alloc")
        val ring = EventRing(1 shl 16)
        val recorder = Recorder(ring, CoreSessionFormat.create(dir, metadata), MadgwickFilter(), onEnd = {})
        val writerId = AtomicLong()
        val v = floatArrayOf(0.1f, 0.2f, 9.8f, 0.01f, 0.02f, 0.03f)
        val streams = SensorStreams.all
        fun batch(from: Int, n: Int) {
            for (i in from until from + n) check(ring.offer(streams[i % 7], 1_000_000_000L + i * 300_000L, 3, v, 6))
        }
        recorder.start()
        batch(0, 7_000) // warm up: stream files opened, classes loaded, code compiled
        while (ring.size > 0) Thread.sleep(1)
        val writer = recorder.writerThread!!
        writerId.set(writer.id)
        val before = threadAllocated(writer.id)
        batch(7_000, 60_000)
        while (ring.size > 0) Thread.sleep(1)
        Thread.sleep(20)
        val perEvent = (threadAllocated(writer.id) - before) / 60_000.0
        recorder.stop()
        assertTrue(recorder.awaitEnd(10_000))
        println("writer thread: %.2f bytes allocated per event (diagnostics rows allocate a small snapshot 10 times a second)".format(perEvent))
        assertTrue(perEvent < 2.0, "writer allocated $perEvent bytes per event")
    }

    /** A recording of a simulated motion through the recorder: the events in timestamp order, as a phone delivers them. */
    private fun recordSimulated(dir: File, seconds: Double, stopAtEnd: Boolean = true): Pair<Recorder, EventRing> {
        val sim = MotionSimulator(SimulationSettings(seed = 7, rateHz = 200.0, durationS = seconds)).run()
        val ring = EventRing(1 shl 16)
        val recorder = Recorder(ring, CoreSessionFormat.create(dir, metadata), MadgwickFilter(), onEnd = {}, flushIntervalNs = 100_000_000L)
        recorder.start()
        val v = FloatArray(6)
        for (s in sim) {
            fun put(stream: SessionStream, dt: Long, x: Double, y: Double, z: Double) {
                v[0] = x.toFloat(); v[1] = y.toFloat(); v[2] = z.toFloat()
                while (!ring.offer(stream, s.timestampNs + dt, 3, v, 3)) error("overflow")
            }
            put(SessionStream.ACCELEROMETER, 0, s.acc.x, s.acc.y, s.acc.z)
            put(SessionStream.MAGNETOMETER, 100_000, s.mag.x, s.mag.y, s.mag.z)
            put(SessionStream.GYROSCOPE, 200_000, s.gyro.x, s.gyro.y, s.gyro.z)
            val q = s.truth
            v[0] = q.x.toFloat(); v[1] = q.y.toFloat(); v[2] = q.z.toFloat(); v[3] = q.w.toFloat(); v[4] = 0.1f
            check(ring.offer(SessionStream.ROTATION_VECTOR, s.timestampNs + 300_000, 3, v, 5))
            if (ring.size > ring.capacity / 2) while (ring.size > 0) Thread.sleep(1)
        }
        if (stopAtEnd) {
            recorder.stop()
            assertTrue(recorder.awaitEnd(10_000))
        }
        return recorder to ring
    }

    /** The filter run again on the written raw streams, merged by timestamp as `fusion replay` does. */
    /**
     * [asFloat]: the CSV's values rounded to float, as the live filter saw them (SensorEvent
     * values are floats; the reader parses the shortest decimal of each float into the nearest
     * double, which differs from the float by up to half a float ulp).
     */
    private fun replayOrientation(reader: SessionReader, settings: FilterSettings = FilterSettings(), asFloat: Boolean = true): List<Pair<Long, DoubleArray>> {
        val filter = MadgwickFilter(settings)
        val out = ArrayList<Pair<Long, DoubleArray>>()
        val v = DoubleArray(3)
        reader.events(setOf(SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE)).use { e ->
            while (e.next()) {
                for (k in 0..2) v[k] = if (asFloat) e.values[k].toFloat().toDouble() else e.values[k]
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
    fun `an exported zip replays to the same orientation as the live output`() {
        val dir = File(tmp, "session_motion")
        recordSimulated(dir, 20.0)
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
            val asDouble = replayOrientation(r, asFloat = false)
            val worstDouble = live.indices.maxOf { angleDeg(live[it].second, asDouble[it].second) }
            println(
                "export: live vs replay of the zip over ${live.size} steps: worst %.2e° (meta.json's filter settings: %.2e°; values read as double, not float: %.2e°)"
                    .format(worst, worstMeta, worstDouble),
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
            assertTrue(worstDouble < 1e-4, "read as doubles: $worstDouble°")
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
        // Wait for at least one flush of the complete data, then "kill": the writer thread is
        // abandoned without closing, and one file ends in a partial row as a killed write leaves it.
        Thread.sleep(400)
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
        recorder.stop()
        recorder.awaitEnd(5_000)
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
        val ring = EventRing(1 shl 16)
        val ended = AtomicReference<RecorderResult>()
        val recorder = Recorder(ring, CoreSessionFormat.create(dir, metadata), MadgwickFilter(), onEnd = { ended.set(it) }, flushIntervalNs = 20_000_000L)
        recorder.start()
        val v = floatArrayOf(0f, 0f, 9.81f)
        var offered = 0
        val t0 = 5_000_000_000L
        while (ended.get() == null && offered < 200_000) {
            val t = t0 + offered * 1_000_000L
            val s = if (offered % 2 == 0) SessionStream.ACCELEROMETER else SessionStream.GYROSCOPE
            v[0] = offered.toFloat()
            if (!ring.offer(s, t, 3, v, 3)) break
            offered++
            if (offered % 500 == 0) Thread.sleep(2)
        }
        assertTrue(recorder.awaitEnd(10_000))
        storage.join(5_000)
        val end = ended.get().end
        assertTrue(end is RecordingEnd.WriteFailed, "$end")
        println("storage failure: ${(end as RecordingEnd.WriteFailed).message} after $limit bytes of gyroscope.csv; ${ended.get().rows} rows handed to the writer")
        assertFalse(ring.offer(SessionStream.GYROSCOPE, Long.MAX_VALUE, 3, v, 3), "the sensors are refused after the failure")

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
