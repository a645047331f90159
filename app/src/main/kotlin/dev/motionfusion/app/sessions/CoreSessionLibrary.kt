package dev.motionfusion.app.sessions

import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.sensormanager.androidOrientation
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import java.io.File

/** Reading sessions with the session format's reader of `fusion-core` (docs/SESSION_FORMAT.md). */
internal object CoreSessionLibrary : SessionLibrary {
    /** From meta.json alone: its per-stream statistics are written when a session is closed or recovered. */
    override fun summary(dir: File): SessionSummary = SessionReader.open(dir.toPath()).use { r ->
        val m = r.metadata
        val sensorStats = SensorStreams.all.mapNotNull { s -> m.streams[s]?.let { s to it } }
        val withRows = sensorStats.filter { it.second.samples > 0 }
        val first = withRows.minOfOrNull { it.second.firstTimestampNs }
        val last = withRows.maxOfOrNull { it.second.lastTimestampNs }
        SessionSummary(
            name = dir.name,
            startWallClockMs = m.startAnchor?.wallClockMs,
            durationNs = if (first != null && last != null) last - first else 0L,
            sizeBytes = SessionStore.sizeOf(dir),
            streams = sensorStats.map { (s, st) -> StreamSummary(s.key, st.samples, if (st.achievedRateHz.isFinite()) st.achievedRateHz else 0.0) },
            fusedRows = m.streams[SessionStream.ORIENTATION]?.samples ?: 0L,
            recovered = m.recovered,
            continues = m.continues?.previousSession,
            gapNs = m.continues?.gapNs,
            stillRecording = m.stillRecording,
            wakeLock = m.wakeLock,
        )
    }

    /** Reads orientation.csv once, keeping every k-th row; k doubles whenever the kept rows reach 2·[maxPoints]. */
    override fun angles(dir: File, maxPoints: Int): AngleSeries = SessionReader.open(dir.toPath()).use { r ->
        val markers = r.markers().map { PlotMarker(it.timestampNs, it.label) }
        if (SessionStream.ORIENTATION !in r.streams) return AngleSeries(FloatArray(0), FloatArray(0), FloatArray(0), FloatArray(0), markers = markers)
        val cap = 2 * maxPoints
        val t = LongArray(cap)
        val a = FloatArray(cap)
        val p = FloatArray(cap)
        val ro = FloatArray(cap)
        var n = 0
        var step = 1L
        var index = 0L
        r.stream(SessionStream.ORIENTATION).use { e ->
            while (e.next()) {
                if (index++ % step != 0L) continue
                if (n == cap) {
                    for (i in 0 until n / 2) {
                        t[i] = t[2 * i]; a[i] = a[2 * i]; p[i] = p[2 * i]; ro[i] = ro[2 * i]
                    }
                    n /= 2
                    step *= 2
                    if ((index - 1) % step != 0L) continue
                }
                val v = e.values
                val angles = androidOrientation(Quaternion(v[0], v[1], v[2], v[3]).normalized().toRotationMatrix())
                t[n] = e.timestampNs; a[n] = angles.azimuthDeg.toFloat(); p[n] = angles.pitchDeg.toFloat(); ro[n] = angles.rollDeg.toFloat()
                n++
            }
        }
        val t0 = if (n > 0) t[0] else 0L
        AngleSeries(FloatArray(n) { ((t[it] - t0) / 1e9).toFloat() }, a.copyOf(n), p.copyOf(n), ro.copyOf(n), t0, markers)
    }

    /**
     * Reads each raw stream's timestamps once and counts them in bins from the session's first
     * timestamp; when a stream reaches past [maxBins] bins the bin width doubles (pairs merged), so
     * an hour at 1 s bins and [maxBins] 1,200 ends at 4-s bins: [maxBins] counts a stream whatever the length.
     */
    override fun rates(dir: File, maxBins: Int): RateSeries = SessionReader.open(dir.toPath()).use { r ->
        require(maxBins >= 2) { "maxBins must be ≥ 2: $maxBins" }
        val present = SensorStreams.all.filter { it in r.streams && (r.metadata.streams[it]?.samples ?: 0L) > 0 }
        if (present.isEmpty()) return RateSeries.EMPTY
        val origin = present.minOf { r.metadata.streams[it]!!.firstTimestampNs }
        var binNs = 1_000_000_000L
        val counts = present.associateWith { IntArray(maxBins) }
        val used = IntArray(present.size)
        for ((k, s) in present.withIndex()) {
            r.stream(s).use { e ->
                while (e.next()) {
                    val dt = e.timestampNs - origin
                    if (dt < 0) continue
                    var bin = dt / binNs
                    while (bin >= maxBins) {
                        binNs *= 2
                        for (c in counts.values) merge(c)
                        for (j in used.indices) used[j] = (used[j] + 1) / 2
                        bin = dt / binNs
                    }
                    counts[s]!![bin.toInt()]++
                    if (bin + 1 > used[k]) used[k] = (bin + 1).toInt()
                }
            }
        }
        val bins = used.max()
        val seconds = binNs / 1e9
        RateSeries(origin, seconds, present.associate { s -> s.key to FloatArray(bins) { (counts[s]!![it] / seconds).toFloat() } })
    }

    /** Pairs of bins merged into the first half (a bin twice as long), the rest zeroed. */
    private fun merge(c: IntArray) {
        for (i in 0 until c.size / 2) c[i] = c[2 * i] + c[2 * i + 1]
        if (c.size % 2 == 1) c[c.size / 2] = c[c.size - 1] else c[c.size / 2] = 0
        for (i in c.size / 2 + 1 until c.size) c[i] = 0
    }
}
