/*
 * SessionMetadata ↔ meta.json. Members are named as in docs/SESSION_FORMAT.md; unknown members
 * are ignored when reading (newer minor versions may add some) and kept by a rewrite of an
 * existing meta.json (writeKeeping), missing ones take their defaults, a member of the wrong
 * type is an error naming its path.
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.io.Json
import dev.motionfusion.core.io.JsonObject

internal object MetadataJson {

    /** The value of the "format" member that marks a meta.json as this project's. */
    const val FORMAT_MARKER = "motion-fusion-session"

    fun write(m: SessionMetadata): String = Json.write(toMap(m))

    /**
     * meta.json of [m], keeping every member of [original] that this version does not write
     * (members of a newer minor version, anywhere in the tree: top level, device, sensors,
     * streams, filter_settings), in their original order. Known members take their value from [m].
     */
    fun writeKeeping(original: Map<*, *>, m: SessionMetadata): String = Json.write(keepUnknown(original, toMap(m), ""))

    private fun keepUnknown(old: Any?, new: Any?, path: String): Any? = when {
        old is Map<*, *> && new is Map<*, *> -> {
            val out = LinkedHashMap<Any?, Any?>()
            for ((k, v) in old) {
                when {
                    new.containsKey(k) -> out[k] = keepUnknown(v, new[k], "$path$k.")
                    // A stream this version knows but no longer has a file: its statistics go.
                    path == "streams." && (SessionStream.ofKey(k.toString()) != null || k == SessionMarkers.KEY) -> {}
                    else -> out[k] = v
                }
            }
            for ((k, v) in new) if (!out.containsKey(k)) out[k] = v
            out
        }
        old is List<*> && new is List<*> && old.size == new.size -> old.indices.map { keepUnknown(old[it], new[it], path) }
        else -> new
    }

    fun toMap(m: SessionMetadata): Map<String, Any?> = linkedMapOf(
        "format" to FORMAT_MARKER,
        "format_version" to m.formatVersion,
        "app_version" to m.appVersion,
        "source" to m.source,
        "device" to linkedMapOf(
            "manufacturer" to m.device.manufacturer,
            "model" to m.device.model,
            "android_version" to m.device.androidVersion,
            "sdk_int" to m.device.sdkInt,
        ),
        "start_anchor" to m.startAnchor?.let(::anchor),
        "anchors" to m.anchors.map(::anchor),
        "end_elapsed_realtime_ns" to m.endElapsedRealtimeNs,
        "end_reason" to m.endReason,
        "complete" to m.complete,
        "recovered" to m.recovered,
        "pauses" to m.pauses.map { linkedMapOf("start_elapsed_realtime_ns" to it.startElapsedRealtimeNs, "end_elapsed_realtime_ns" to it.endElapsedRealtimeNs) },
        "sensors" to m.sensors.map { s ->
            linkedMapOf(
                "stream" to s.stream.key,
                "name" to s.name,
                "vendor" to s.vendor,
                "version" to s.version,
                "type" to s.type,
                "string_type" to s.stringType,
                "maximum_range" to s.maximumRange,
                "resolution" to s.resolution,
                "power_ma" to s.powerMa,
                "min_delay_us" to s.minDelayUs,
                "max_delay_us" to s.maxDelayUs,
                "fifo_reserved_event_count" to s.fifoReservedEventCount,
                "fifo_max_event_count" to s.fifoMaxEventCount,
                "wake_up" to s.wakeUp,
                "requested_period_us" to s.requestedPeriodUs,
                "max_report_latency_us" to s.maxReportLatencyUs,
            )
        },
        "streams" to m.streams.entries.sortedBy { it.key.ordinal }.associateTo(LinkedHashMap<String, Any?>()) { (k, v) -> k.key to stats(k.fileName, v) }
            .also { map -> m.markers?.let { map[SessionMarkers.KEY] = stats(SessionMarkers.FILE_NAME, it) } },
        "filter_settings" to m.filterSettings?.let(::settings),
        "frames" to FRAMES,
    ).also { map ->
        // Written only when set: sessions without them stay as they were.
        if (m.stillRecording) map["still_recording"] = true
        m.continues?.let {
            map["continues"] = linkedMapOf(
                "session" to it.previousSession,
                "gap_start_elapsed_realtime_ns" to it.gapStartElapsedRealtimeNs,
                "gap_end_elapsed_realtime_ns" to it.gapEndElapsedRealtimeNs,
            )
        }
        m.calibration?.let { map["calibration"] = CalibrationJson.tree(it.calibration) + (APPLIED_IN_LIVE_FILTER to it.appliedInLiveFilter) }
        m.clockLink?.let { map["clock_link"] = it }
        m.remoteStart?.let {
            map["remote_start"] = linkedMapOf("by" to it.by, "laptop_clock" to it.laptopClock, "laptop_ns" to it.laptopNs, "elapsed_realtime_ns" to it.elapsedRealtimeNs)
        }
        m.wakeLock?.let { map["wake_lock"] = linkedMapOf("held" to it.held, "reason" to it.reason, "forced_by" to it.forcedBy.map { s -> s.key }) }
    }

    /**
     * The frames of every file of a session, named in its meta.json for readers that do not know
     * this format (docs/SESSION_FORMAT.md, "Frames"; docs/CONVENTIONS.md). The same for every
     * session: readers take the frames from the format, this member only states them.
     */
    private val FRAMES: Map<String, String> = linkedMapOf(
        // Short: meta.json is rewritten at every anchor and pause while recording.
        "device" to "android_sensor: x right, y up, z out of screen",
        "world" to "ENU: x east, y magnetic north, z up",
        "quaternion" to "qw,qx,qy,qz Hamilton, device to world",
        "rotation_vector" to "Android values qx,qy,qz,qw, device to world",
        "time" to "SensorEvent.timestamp ns",
    )

    /** The member of `calibration` that says whether the live filter used it. */
    private const val APPLIED_IN_LIVE_FILTER = "applied_in_live_filter"

    private fun stats(file: String, v: StreamStats) = linkedMapOf(
        "file" to file,
        "samples" to v.samples,
        "first_timestamp_ns" to v.firstTimestampNs,
        "last_timestamp_ns" to v.lastTimestampNs,
        "achieved_rate_hz" to v.achievedRateHz,
        "interval_std_ms" to v.intervalStdMs,
        "backwards" to v.backwards,
        "duplicates" to v.duplicates,
    )

    private fun parseStats(s: JsonObject) = StreamStats(
        s.long("samples", 0L), s.long("first_timestamp_ns", 0L), s.long("last_timestamp_ns", 0L),
        s.double("achieved_rate_hz"), s.double("interval_std_ms"), s.long("backwards", 0L), s.long("duplicates", 0L),
    )

    private fun anchor(a: ClockAnchor) = linkedMapOf("wall_clock_ms" to a.wallClockMs, "elapsed_realtime_ns" to a.elapsedRealtimeNs)

    fun settings(s: FilterSettings): Map<String, Any?> = FilterSettingDescriptors.all.associateTo(LinkedHashMap()) { it.jsonKey to it.storedValue(s) }

    fun parse(text: String, sourceName: String): SessionMetadata {
        val r = Json.document(text, sourceName).rootObject()
        val version = r.int("format_version", -1)
        if (version < 1) throw r.error("format_version", "missing or not a positive integer")
        if (version > SessionMetadata.FORMAT_VERSION) {
            throw r.error("format_version", "$version is newer than this reader (${SessionMetadata.FORMAT_VERSION}); update fusion")
        }
        val device = r.obj("device")
        return SessionMetadata(
            formatVersion = version,
            appVersion = r.string("app_version"),
            source = r.string("source"),
            device = DeviceInfo(device.string("manufacturer"), device.string("model"), device.string("android_version"), device.int("sdk_int", 0)),
            startAnchor = r.objOrNull("start_anchor")?.let(::parseAnchor),
            anchors = r.list("anchors").map(::parseAnchor),
            sensors = r.list("sensors").map { s ->
                val key = s.string("stream")
                val stream = SessionStream.ofKey(key) ?: throw s.error("stream", "unknown stream '$key'")
                SensorInfo(
                    stream = stream,
                    name = s.string("name"), vendor = s.string("vendor"), version = s.int("version", 0),
                    type = s.int("type", stream.androidType), stringType = s.string("string_type"),
                    maximumRange = s.double("maximum_range"), resolution = s.double("resolution"), powerMa = s.double("power_ma"),
                    minDelayUs = s.int("min_delay_us", 0), maxDelayUs = s.int("max_delay_us", 0),
                    fifoReservedEventCount = s.int("fifo_reserved_event_count", 0), fifoMaxEventCount = s.int("fifo_max_event_count", 0),
                    wakeUp = s.bool("wake_up", false),
                    requestedPeriodUs = s.int("requested_period_us", 0), maxReportLatencyUs = s.int("max_report_latency_us", 0),
                )
            },
            filterSettings = r.objOrNull("filter_settings")?.let(::parseSettings),
            pauses = r.list("pauses").map { Pause(it.long("start_elapsed_realtime_ns", 0L), it.longOrNull("end_elapsed_realtime_ns")) },
            complete = r.bool("complete", false),
            recovered = r.bool("recovered", false),
            endElapsedRealtimeNs = r.longOrNull("end_elapsed_realtime_ns"),
            endReason = r.string("end_reason"),
            streams = r.objOrNull("streams")?.let { o ->
                o.keys().mapNotNull { k -> SessionStream.ofKey(k)?.let { it to parseStats(o.obj(k)) } }.toMap()
            } ?: emptyMap(),
            markers = r.objOrNull("streams")?.objOrNull(SessionMarkers.KEY)?.let(::parseStats),
            calibration = r.objOrNull("calibration")?.let { SessionCalibration(CalibrationJson.parse(it), it.bool(APPLIED_IN_LIVE_FILTER, false)) },
            stillRecording = r.bool("still_recording", false),
            continues = r.objOrNull("continues")?.let {
                Continuation(it.string("session"), it.longOrNull("gap_start_elapsed_realtime_ns"), it.long("gap_end_elapsed_realtime_ns", 0L))
            },
            clockLink = r.stringOrNull("clock_link"),
            remoteStart = r.objOrNull("remote_start")?.let {
                RemoteStart(it.string("by"), it.stringOrNull("laptop_clock"), it.long("laptop_ns", 0L), it.long("elapsed_realtime_ns", 0L))
            },
            wakeLock = r.objOrNull("wake_lock")?.let { w ->
                // A stream this version does not know (a newer one's) is left out of the list, as in `streams`.
                WakeLockUse(w.bool("held", true), w.string("reason"), w.strings("forced_by").mapNotNull(SessionStream::ofKey))
            },
        )
    }

    private fun parseAnchor(o: JsonObject) = ClockAnchor(o.long("wall_clock_ms", 0L), o.long("elapsed_realtime_ns", 0L))

    /** Members missing from stored settings take the value of their time ([FilterSettingDescriptor.valueWhenAbsent]) or the default. */
    private fun parseSettings(o: JsonObject): FilterSettings {
        var s = FilterSettings()
        for (d in FilterSettingDescriptors.all) {
            val v = o.raw(d.jsonKey) ?: d.valueWhenAbsent ?: continue
            s = try {
                d.with(s, v)
            } catch (e: IllegalArgumentException) {
                throw o.error(d.jsonKey, "invalid filter setting: ${e.message}")
            }
        }
        return s
    }
}
