package dev.motionfusion.app.sessions

import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.sensormanager.androidOrientation
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionStream
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
}
