# The download half of gradlew.bat (the same steps as gradlew): reads distributionUrl and
# distributionSha256Sum from gradle-wrapper.properties beside this file, downloads the distribution
# once into %GRADLE_USER_HOME%\wrapper\dists (default %USERPROFILE%\.gradle), refuses it unless its
# SHA-256 is the one given, unpacks it aside and moves it into place only when complete (marked by a
# .complete file written last), and prints the path of its bin\gradle.bat for gradlew.bat to run.
$ErrorActionPreference = 'Stop'
$ProgressPreference = 'SilentlyContinue'

function Fail([string] $message) {
    [Console]::Error.WriteLine("gradlew: $message")
    exit 1
}

$propsFile = Join-Path $PSScriptRoot 'gradle-wrapper.properties'
if (-not (Test-Path -LiteralPath $propsFile)) { Fail "$propsFile not found" }
$props = @{}
foreach ($line in Get-Content -LiteralPath $propsFile) {
    if ($line -match '^\s*([^#!][^=]*?)\s*=\s*(.*?)\s*$') {
        $props[$Matches[1]] = $Matches[2] -replace '\\(.)', '$1'
    }
}
$url = $props['distributionUrl']
$sum = $props['distributionSha256Sum']
if (-not $url) { Fail "no distributionUrl in $propsFile" }
if (-not $sum) { Fail "no distributionSha256Sum in $propsFile: the distribution would run unchecked" }

$zipName = $url.Substring($url.LastIndexOf('/') + 1)
$distName = $zipName -replace '\.zip$', ''
$userHome = if ($env:GRADLE_USER_HOME) { $env:GRADLE_USER_HOME } else { Join-Path $env:USERPROFILE '.gradle' }
$dists = Join-Path (Join-Path (Join-Path $userHome 'wrapper') 'dists') $distName
$gradleHome = Join-Path $dists ('script-' + $sum.ToLowerInvariant())
$marker = Join-Path $gradleHome '.complete'

if (-not (Test-Path -LiteralPath $marker)) {
    if (Test-Path -LiteralPath $gradleHome) { Remove-Item -LiteralPath $gradleHome -Recurse -Force }
    New-Item -ItemType Directory -Force -Path $dists | Out-Null
    $id = [guid]::NewGuid().ToString('N')
    $tmpZip = Join-Path $dists "$zipName.$id.part"
    $tmpDir = Join-Path $dists "unzip.$id"
    try {
        [Console]::Error.WriteLine("Downloading $url")
        [Net.ServicePointManager]::SecurityProtocol = [Net.ServicePointManager]::SecurityProtocol -bor [Net.SecurityProtocolType]::Tls12
        try { Invoke-WebRequest -UseBasicParsing -Uri $url -OutFile $tmpZip } catch { Fail "download of $url failed: $($_.Exception.Message)" }
        $actual = (Get-FileHash -LiteralPath $tmpZip -Algorithm SHA256).Hash.ToLowerInvariant()
        if ($actual -ne $sum.ToLowerInvariant()) { Fail "$zipName has SHA-256 $actual, not distributionSha256Sum $sum; refused" }
        Expand-Archive -LiteralPath $tmpZip -DestinationPath $tmpDir
        $top = @(Get-ChildItem -LiteralPath $tmpDir)
        if ($top.Count -ne 1 -or -not (Test-Path -LiteralPath (Join-Path $top[0].FullName 'bin\gradle.bat'))) { Fail "$zipName holds no single gradle-*\bin\gradle.bat" }
        Set-Content -LiteralPath (Join-Path $tmpDir '.complete') -Value $top[0].Name
        if (-not (Test-Path -LiteralPath $marker)) { Move-Item -LiteralPath $tmpDir -Destination $gradleHome }
    } finally {
        if (Test-Path -LiteralPath $tmpZip) { Remove-Item -LiteralPath $tmpZip -Force }
        if (Test-Path -LiteralPath $tmpDir) { Remove-Item -LiteralPath $tmpDir -Recurse -Force }
    }
}
$top = (Get-Content -LiteralPath $marker -TotalCount 1).Trim()
$gradle = Join-Path (Join-Path (Join-Path $gradleHome $top) 'bin') 'gradle.bat'
if (-not (Test-Path -LiteralPath $gradle)) { Fail "$gradle missing; remove $gradleHome and run again" }
Write-Output $gradle
